// Deskew: one pose interpolation per distinct firing time, then a rigid transform per point.
#include <ogf/fusion/deskew.hpp>

#include <algorithm>

namespace ogf::fusion {

ScanTimeSpan timeSpanOf(const ScanPoints& points) {
  if (points.size() == 0) return {points.start_utime, points.start_utime};
  const auto [lo, hi] = std::minmax_element(points.time_offset_ns.begin(), points.time_offset_ns.end());
  const std::size_t first = static_cast<std::size_t>(lo - points.time_offset_ns.begin());
  const std::size_t last = static_cast<std::size_t>(hi - points.time_offset_ns.begin());
  return {points.utimeOf(first), points.utimeOf(last)};
}

Deskew::Deskew(const Eigen::Isometry3d& body_from_sensor) : body_from_sensor_(body_from_sensor) {}

PoseCoverage Deskew::place(const ScanPoints& points, const PoseBuffer& poses, std::vector<Eigen::Vector3d>& origins,
                           std::vector<Eigen::Vector3d>& endpoints) {
  last_interpolations_ = 0;
  origins.clear();
  endpoints.clear();
  const ScanTimeSpan span = timeSpanOf(points);
  // All or nothing: check the whole span before writing anything.
  if (const PoseCoverage c = poses.coverage(span.begin_utime, span.end_utime); c != PoseCoverage::kCovered) {
    return c;
  }
  const std::size_t n = points.size();
  origins.resize(n);
  endpoints.resize(n);
  std::int64_t cached_utime = 0;
  Eigen::Isometry3d odom_from_sensor = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t t = points.utimeOf(i);
    if (i == 0 || t != cached_utime) {
      // Covered: t lies within the span checked above.
      odom_from_sensor = poses.interpolate(t).pose.odomFromBody() * body_from_sensor_;
      cached_utime = t;
      ++last_interpolations_;
    }
    const Eigen::Vector3d p(static_cast<double>(points.x[i]), static_cast<double>(points.y[i]),
                            static_cast<double>(points.z[i]));
    origins[i] = odom_from_sensor.translation();
    endpoints[i] = odom_from_sensor * p;
  }
  return PoseCoverage::kCovered;
}

}  // namespace ogf::fusion
