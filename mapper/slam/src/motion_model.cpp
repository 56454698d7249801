// The odometry motion model: its noise, its density and its sampler.
#include "ogf/slam/motion_model.hpp"

#include <algorithm>
#include <cmath>

#include "config_errors.hpp"

namespace ogf::slam {

Status MotionModelConfig::validate() const {
  const struct {
    const char* name;
    double v;
  } fields[] = {{"srr", srr}, {"srt", srt}, {"str", str}, {"stt", stt}, {"sxy", sxy}};
  for (const auto& f : fields) {
    if (!(f.v >= 0.0) || !std::isfinite(f.v)) return fieldError(f.name, "must be a finite number >= 0", f.v);
  }
  if (!(min_sigma_m > 0.0) || !std::isfinite(min_sigma_m))
    return fieldError("min_sigma_m", "must be > 0", min_sigma_m);
  if (!(min_sigma_rad > 0.0) || !std::isfinite(min_sigma_rad)) {
    return fieldError("min_sigma_rad", "must be > 0", min_sigma_rad);
  }
  return okStatus();
}

double MotionGaussian::logDensity(const Pose2& x) const {
  const Pose2 d = between(previous, x);
  const double ex = (d.x - step.x) / sigma_x, ey = (d.y - step.y) / sigma_y;
  const double et = normalizeAngle(d.theta - step.theta) / sigma_theta;
  return -0.5 * (ex * ex + ey * ey + et * et);
}

MotionGaussian MotionModel::predict(const Pose2& previous, const Pose2& odometry_step) const {
  const double ax = std::abs(odometry_step.x), ay = std::abs(odometry_step.y),
               at = std::abs(odometry_step.theta);
  MotionGaussian g;
  g.previous = previous;
  g.step = odometry_step;
  g.sigma_x = std::max(config_.min_sigma_m, config_.srr * ax + config_.sxy * ay + config_.str * at);
  g.sigma_y = std::max(config_.min_sigma_m, config_.srr * ay + config_.sxy * ax + config_.str * at);
  g.sigma_theta = std::max(config_.min_sigma_rad, config_.stt * at + config_.srt * std::hypot(ax, ay));
  return g;
}

Pose2 MotionModel::sample(const MotionGaussian& g, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const double nx = n(rng), ny = n(rng), nt = n(rng);
  const Pose2 noisy{g.step.x + g.sigma_x * nx, g.step.y + g.sigma_y * ny,
                    normalizeAngle(g.step.theta + g.sigma_theta * nt)};
  return compose(g.previous, noisy);
}

}  // namespace ogf::slam
