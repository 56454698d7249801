// Planar rigid transforms on Pose2 (x, y, theta): composition, inverse and angle normalisation, as the
// benchmark's metric and the result log need them.
#pragma once

#include <cmath>
#include <numbers>

#include "ogf/slam_io/carmen_log.hpp"

namespace ogf::slam_io::detail {

// The angle mapped to (-pi, pi].
inline double normalizeAngle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);  // [-pi, pi]
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

// a * b: b expressed in a's frame, moved to the world frame.
inline Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalizeAngle(a.theta + b.theta)};
}

// a^-1.
inline Pose2 inverse(const Pose2& a) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, normalizeAngle(-a.theta)};
}

// a^-1 * b: the motion from a to b in a's frame.
inline Pose2 between(const Pose2& a, const Pose2& b) { return compose(inverse(a), b); }

}  // namespace ogf::slam_io::detail
