// The shared trajectory tree: order, release of long chains, the pose of scans between processed ones.
#include <gtest/gtest.h>

#include <memory>
#include <ogf/slam/trajectory.hpp>

namespace ogf::slam {
namespace {

TEST(Trajectory, CollectsOldestFirstAndBranchesShareTheirPast) {
  auto root = std::make_shared<const TrajectoryNode>(Pose2{0, 0, 0}, Pose2{0, 0, 0}, 0, nullptr);
  auto a = std::make_shared<const TrajectoryNode>(Pose2{1, 0, 0}, Pose2{1, 0, 0}, 5, root);
  auto b = std::make_shared<const TrajectoryNode>(Pose2{1, 1, 0}, Pose2{1, 0, 0}, 5, root);
  const auto ta = collectTrajectory(a), tb = collectTrajectory(b);
  ASSERT_EQ(ta.size(), 2U);
  EXPECT_EQ(ta[0].scan_id, 0U);
  EXPECT_EQ(ta[1].scan_id, 5U);
  EXPECT_DOUBLE_EQ(tb[1].pose.y, 1.0);
  EXPECT_EQ(a->parent.get(), b->parent.get());
}

TEST(Trajectory, AMillionNodeHistoryIsReleasedWithoutRecursion) {
  std::shared_ptr<const TrajectoryNode> head;
  for (std::uint64_t i = 0; i < 1000000; ++i) {
    head = std::make_shared<const TrajectoryNode>(Pose2{}, Pose2{}, i, head);
  }
  head.reset();  // would overflow the stack with the default recursive release
  SUCCEED();
}

TEST(Trajectory, ScansBetweenNodesGetTheNodePoseAndTheOdometrySince) {
  // The node at scan 10 was corrected by +0.5 m in y and a quarter turn relative to odometry.
  const std::vector<TrajectoryPoint> pts{{0, {0, 0, 0}, {0, 0, 0}},
                                         {10, {2, 0.5, 1.5707963267948966}, {2, 0, 0}}};
  // Scan 12: odometry moved 1 m ahead of scan 10's odometry pose; in the corrected frame that is +y.
  const Pose2 p = correctedPose(pts, 12, {3, 0, 0});
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 1.5, 1e-12);
  // Scan 5 uses node 0 (identity correction).
  const Pose2 q = correctedPose(pts, 5, {1, 0, 0.1});
  EXPECT_NEAR(q.x, 1.0, 1e-12);
  EXPECT_NEAR(q.theta, 0.1, 1e-12);
}

}  // namespace
}  // namespace ogf::slam
