// A planar pose (x, y, theta) and the SE(2) algebra the 2-D SLAM layer needs: composition (⊕), inverse
// and the relative motion between two poses (a⁻¹ ⊕ b), in the notation of Lu & Milios / GMapping's
// absoluteSum and absoluteDifference.
#pragma once

#include <cmath>
#include <numbers>

namespace ogf::slam {

// An angle wrapped to (-pi, pi].
inline double normalizeAngle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);  // [-pi, pi]
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

struct Pose2 {
  double x = 0.0;      // metres
  double y = 0.0;      // metres
  double theta = 0.0;  // radians, (-pi, pi]
};

// a ⊕ b: the pose b, given in the frame of a, expressed in a's parent frame.
inline Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalizeAngle(a.theta + b.theta)};
}

// a⁻¹, so that compose(inverse(a), a) is the identity.
inline Pose2 inverse(const Pose2& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  return {-c * a.x - s * a.y, s * a.x - c * a.y, normalizeAngle(-a.theta)};
}

// a⁻¹ ⊕ b: the motion from a to b in the frame of a (what odometry reports between two instants).
inline Pose2 between(const Pose2& a, const Pose2& b) { return compose(inverse(a), b); }

inline double translationNorm(const Pose2& p) { return std::hypot(p.x, p.y); }

}  // namespace ogf::slam
