// The true trajectory: through the waypoints at constant speed with a smoothly turning heading.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ogf/sim/trajectory.hpp"

namespace ogf::sim {
namespace {

double yawOf(const Pose& p) {
  const Eigen::Vector3d x = p.orientation * Eigen::Vector3d::UnitX();
  return std::atan2(x.y(), x.x());
}

TEST(SimTrajectory, LoopMovesAtConstantSpeedAndPassesEveryWaypoint) {
  TrajectorySpec spec{{{0, 0, 0}, {6, 0, 0}, {6, 3, 0}, {0, 3, 0}}, 1.5, true, 0.0};
  const auto traj = Trajectory::build(spec);
  ASSERT_TRUE(traj.ok()) << traj.error().message;
  const double dt = 0.01;
  for (double t = dt; t < 20.0; t += dt) {
    const double step = (traj->poseAt(t).position - traj->poseAt(t - dt).position).norm();
    ASSERT_NEAR(step, 1.5 * dt, 1.5 * dt * 0.02) << "t " << t;  // chord ≈ arc at 1 cm spacing
  }
  for (const auto& w : spec.waypoints) {
    double best = 1e9;
    for (double t = 0; t < traj->length() / 1.5; t += 0.002) best = std::min(best, (traj->poseAt(t).position - w).norm());
    EXPECT_LT(best, 0.01) << w.transpose();
  }
  // Closed: one lap later the body is back where it started.
  EXPECT_LT((traj->poseAt(traj->length() / 1.5).position - traj->poseAt(0).position).norm(), 0.02);
}

TEST(SimTrajectory, HeadingFollowsThePathWithoutJumps) {
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}, {5, 0, 0}, {5, 5, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  const double dt = 0.01;
  for (double t = dt; t < traj->length() - 0.05; t += dt) {
    const Eigen::Vector3d v = traj->poseAt(t + dt).position - traj->poseAt(t - dt).position;
    const double along = std::atan2(v.y(), v.x());
    double d = yawOf(traj->poseAt(t)) - along;
    d = std::remainder(d, 2 * std::numbers::pi);
    EXPECT_LT(std::abs(d), 0.02) << "t " << t;
    double turn = std::remainder(yawOf(traj->poseAt(t)) - yawOf(traj->poseAt(t - dt)), 2 * std::numbers::pi);
    EXPECT_LT(std::abs(turn), 0.05) << "heading jumps at t " << t;
  }
  // An open path stops at its last waypoint.
  EXPECT_LT((traj->poseAt(1000.0).position - Eigen::Vector3d(5, 5, 0)).norm(), 1e-9);
}

TEST(SimTrajectory, SingleWaypointIsAStaticPoseWithItsYaw) {
  const auto traj = Trajectory::build(TrajectorySpec{{{1, 2, 0}}, 1.0, false, 0.5});
  ASSERT_TRUE(traj.ok());
  for (double t : {0.0, 3.0, 100.0}) {
    EXPECT_EQ(traj->poseAt(t).position, Eigen::Vector3d(1, 2, 0));
    EXPECT_NEAR(yawOf(traj->poseAt(t)), 0.5, 1e-12);
  }
}

TEST(SimTrajectory, EmptyOrDegenerateSpecsAreRefused) {
  EXPECT_FALSE(Trajectory::build(TrajectorySpec{}).ok());
  EXPECT_FALSE(Trajectory::build(TrajectorySpec{{{1, 1, 0}, {1, 1, 0}}, 1.0, false, 0.0}).ok());
  EXPECT_FALSE(Trajectory::build(TrajectorySpec{{{0, 0, 0}, {1, 1, 0}}, 0.0, false, 0.0}).ok());
}

}  // namespace
}  // namespace ogf::sim
