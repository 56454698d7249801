// The body's path: a centripetal Catmull–Rom spline through the waypoints (it passes through every
// waypoint, has a continuous tangent, and never forms cusps or self-loops), resampled by arc length so
// the body moves at constant speed with a smoothly turning heading.
#include "ogf/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ogf::sim {
namespace {

constexpr double kStep = 0.01;          // arc-length spacing of the resampled path, metres
constexpr int kSamplesPerSegment = 400;  // dense spline samples per waypoint segment

// Knot spacing of the centripetal parameterisation (alpha = 1/2), kept away from zero so repeated
// waypoints do not divide by zero.
double knot(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::max(std::sqrt((b - a).norm()), 1e-6);
}

// The point at u in [0, 1] on the segment p1 → p2 (Barry–Goldman pyramid).
Eigen::Vector3d catmullRom(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                           const Eigen::Vector3d& p3, double u) {
  const double t0 = 0.0;
  const double t1 = t0 + knot(p0, p1);
  const double t2 = t1 + knot(p1, p2);
  const double t3 = t2 + knot(p2, p3);
  const double t = t1 + u * (t2 - t1);
  const Eigen::Vector3d a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1;
  const Eigen::Vector3d a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2;
  const Eigen::Vector3d a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3;
  const Eigen::Vector3d b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2;
  const Eigen::Vector3d b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3;
  return (t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2;
}

Eigen::Quaterniond yawQuaternion(double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
}

}  // namespace

Result<Trajectory> Trajectory::build(const TrajectorySpec& spec) {
  if (spec.waypoints.empty()) return Error{"trajectory: no waypoints"};
  Trajectory traj;
  traj.loop_ = spec.loop;
  traj.speed_ = spec.speed;
  std::vector<Eigen::Vector3d> pts = spec.waypoints;
  if (pts.size() >= 2 && spec.loop && (pts.front() - pts.back()).norm() < 1e-9) pts.pop_back();
  if (pts.size() == 1) {
    traj.positions_ = {pts.front()};
    traj.headings_ = {spec.yaw};
    return traj;
  }
  if (!(spec.speed > 0.0)) return Error{"trajectory: speed must be positive for a moving trajectory"};

  // Dense samples of the spline, segment by segment.
  const std::size_t n = pts.size();
  auto point = [&](std::ptrdiff_t i) -> Eigen::Vector3d {
    const auto sn = static_cast<std::ptrdiff_t>(n);
    if (spec.loop) return pts[static_cast<std::size_t>(((i % sn) + sn) % sn)];
    if (i < 0) return 2.0 * pts[0] - pts[1];  // reflected phantom ends
    if (i >= sn) return 2.0 * pts[n - 1] - pts[n - 2];
    return pts[static_cast<std::size_t>(i)];
  };
  const std::size_t segments = spec.loop ? n : n - 1;
  std::vector<Eigen::Vector3d> dense;
  dense.reserve(segments * kSamplesPerSegment + 1);
  for (std::size_t s = 0; s < segments; ++s) {
    const auto i = static_cast<std::ptrdiff_t>(s);
    for (int k = 0; k < kSamplesPerSegment; ++k) {
      dense.push_back(catmullRom(point(i - 1), point(i), point(i + 1), point(i + 2),
                                 static_cast<double>(k) / kSamplesPerSegment));
    }
  }
  dense.push_back(spec.loop ? pts[0] : pts[n - 1]);

  // Resample every kStep metres of arc length.
  std::vector<double> arc(dense.size(), 0.0);
  for (std::size_t i = 1; i < dense.size(); ++i) arc[i] = arc[i - 1] + (dense[i] - dense[i - 1]).norm();
  traj.length_ = arc.back();
  if (traj.length_ < 1e-6) return Error{"trajectory: the waypoints do not span a path of positive length"};
  const auto count = static_cast<std::size_t>(std::floor(traj.length_ / kStep)) + 1;
  traj.positions_.reserve(count + 1);
  std::size_t j = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double s = static_cast<double>(i) * kStep;
    while (j + 2 < arc.size() && arc[j + 1] < s) ++j;
    const double span = arc[j + 1] - arc[j];
    const double f = span > 0.0 ? std::clamp((s - arc[j]) / span, 0.0, 1.0) : 0.0;
    traj.positions_.push_back(dense[j] + f * (dense[j + 1] - dense[j]));
  }
  traj.positions_.push_back(dense.back());  // exactly at s = length

  // Heading along the path, from central differences, unwrapped so interpolation never jumps by 2π.
  const std::size_t m = traj.positions_.size();
  traj.headings_.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    Eigen::Vector3d before;
    Eigen::Vector3d after;
    if (spec.loop) {
      before = i == 0 ? traj.positions_[m - 2] : traj.positions_[i - 1];
      after = i + 1 == m ? traj.positions_[1] : traj.positions_[i + 1];
    } else {
      before = traj.positions_[i == 0 ? 0 : i - 1];
      after = traj.positions_[std::min(i + 1, m - 1)];
    }
    const Eigen::Vector3d d = after - before;
    double h = std::atan2(d.y(), d.x());
    if (i > 0) {
      const double prev = traj.headings_[i - 1];
      h += 2.0 * std::numbers::pi * std::round((prev - h) / (2.0 * std::numbers::pi));
    }
    traj.headings_[i] = h;
  }
  return traj;
}

Pose Trajectory::poseAt(double t) const {
  if (positions_.size() == 1) return Pose{positions_.front(), yawQuaternion(headings_.front())};
  double s = std::max(0.0, t) * speed_;
  s = loop_ ? std::fmod(s, length_) : std::min(s, length_);
  const std::size_t last = positions_.size() - 1;
  auto i = static_cast<std::size_t>(std::floor(s / kStep));
  i = std::min(i, last - 1);
  const double s0 = static_cast<double>(i) * kStep;
  const double s1 = i + 1 == last ? length_ : s0 + kStep;
  const double f = s1 > s0 ? std::clamp((s - s0) / (s1 - s0), 0.0, 1.0) : 0.0;
  const Eigen::Vector3d p = positions_[i] + f * (positions_[i + 1] - positions_[i]);
  const double yaw = headings_[i] + f * (headings_[i + 1] - headings_[i]);
  return Pose{p, yawQuaternion(yaw)};
}

}  // namespace ogf::sim
