// The height-band projection of a 3-D scan to a planar scan.
#include "ogf/slam/planar_projection.hpp"

#include <cmath>
#include <numbers>

#include "config_errors.hpp"

namespace ogf::slam {

Status PlanarProjectionConfig::validate() const {
  if (!std::isfinite(z_min_m) || !std::isfinite(z_max_m) || !(z_max_m > z_min_m)) {
    return fieldError("z_max_m", "must be finite and > z_min_m", z_max_m);
  }
  if (!(min_range_m >= 0.0)) return fieldError("min_range_m", "must be >= 0", min_range_m);
  if (!(max_range_m > min_range_m) || !std::isfinite(max_range_m)) {
    return fieldError("max_range_m", "must be finite and > min_range_m", max_range_m);
  }
  if (beams < 4 || beams > 100000) return fieldError("beams", "must be in [4, 100000]", beams);
  return okStatus();
}

PlanarScan projectToPlanarScan(std::span<const Eigen::Vector3f> points_body,
                               const PlanarProjectionConfig& config) {
  PlanarScan scan;
  const double two_pi = 2.0 * std::numbers::pi;
  scan.angle_increment_rad = two_pi / config.beams;
  scan.angle_min_rad = -std::numbers::pi;
  scan.max_range_m = config.max_range_m;
  scan.ranges_m.assign(static_cast<std::size_t>(config.beams), static_cast<float>(config.max_range_m));
  for (const Eigen::Vector3f& p : points_body) {
    const double z = p.z();
    if (!(z >= config.z_min_m && z <= config.z_max_m)) continue;  // also drops NaN
    const double x = p.x(), y = p.y();
    const double r = std::hypot(x, y);
    if (!(r >= config.min_range_m && r < config.max_range_m)) continue;
    // Bin k covers bearings [−π + (k − ½)·inc, −π + (k + ½)·inc), wrapping at ±π.
    const double a = std::atan2(y, x) - scan.angle_min_rad;  // [0, 2π]
    auto k = static_cast<long>(std::floor(a / scan.angle_increment_rad + 0.5));
    if (k >= config.beams) k -= config.beams;
    float& bin = scan.ranges_m[static_cast<std::size_t>(k)];
    bin = std::min(bin, static_cast<float>(r));
  }
  return scan;
}

}  // namespace ogf::slam
