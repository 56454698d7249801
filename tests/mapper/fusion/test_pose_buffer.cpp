// PoseBuffer: exact interpolation on constructed trajectories, slerp along the short arc, coverage without
// extrapolation, validation and its counters, eviction.
#include <ogf/fusion/pose_buffer.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace ogf::fusion {
namespace {

PoseBufferConfig smallConfig(std::size_t capacity = 100) {
  PoseBufferConfig c;
  c.capacity = capacity;
  return c;
}

Eigen::Quaterniond yaw(double rad) { return Eigen::Quaterniond(Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ())); }

Pose pose(std::int64_t utime, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) { return {utime, p, q}; }

TEST(PoseBuffer, InterpolatesConstantVelocityAndConstantYawRateExactly) {
  PoseBuffer buffer(smallConfig(200));  // 101 poses
  const Eigen::Vector3d v(1.5, -0.4, 0.1);  // m/s
  const double w = 0.8;                     // rad/s about z
  for (std::int64_t t = 0; t <= 1'000'000; t += 10'000) {
    const double s = static_cast<double>(t) * 1e-6;
    ASSERT_TRUE(buffer.insert(pose(t, v * s, yaw(w * s))).accepted());
  }
  for (const std::int64_t t : {0L, 1L, 4'999L, 5'000L, 123'457L, 999'999L, 1'000'000L}) {
    const PoseLookup got = buffer.interpolate(t);
    ASSERT_TRUE(got.ok()) << t;
    const double s = static_cast<double>(t) * 1e-6;
    EXPECT_EQ(got.pose.utime, t);
    EXPECT_LT((got.pose.position - v * s).norm(), 1e-12) << t;
    EXPECT_LT(got.pose.orientation.angularDistance(yaw(w * s)), 1e-12) << t;
  }
}

TEST(PoseBuffer, ReturnsStoredPosesExactlyAtTheirTimes) {
  PoseBuffer buffer(smallConfig());
  const Pose a = pose(100, {1, 2, 3}, yaw(0.3));
  const Pose b = pose(200, {4, 5, 6}, yaw(-1.0));
  ASSERT_TRUE(buffer.insert(a).accepted());
  ASSERT_TRUE(buffer.insert(b).accepted());
  EXPECT_EQ(buffer.interpolate(100).pose.position, a.position);
  EXPECT_EQ(buffer.interpolate(200).pose.position, b.position);
  EXPECT_TRUE(buffer.interpolate(200).pose.orientation.coeffs().isApprox(b.orientation.coeffs(), 0.0));
}

TEST(PoseBuffer, SlerpTakesTheShortArcWhateverTheQuaternionSigns) {
  PoseBuffer buffer(smallConfig());
  // 170° and -170° of yaw are 20° apart; store the second with a negated quaternion as well.
  const double deg = std::numbers::pi / 180.0;
  Eigen::Quaterniond end = yaw(-170.0 * deg);
  end.coeffs() = -end.coeffs();
  ASSERT_TRUE(buffer.insert(pose(0, Eigen::Vector3d::Zero(), yaw(170.0 * deg))).accepted());
  ASSERT_TRUE(buffer.insert(pose(1000, Eigen::Vector3d::Zero(), end)).accepted());
  const PoseLookup mid = buffer.interpolate(500);
  ASSERT_TRUE(mid.ok());
  EXPECT_LT(mid.pose.orientation.angularDistance(yaw(180.0 * deg)), 1e-9);
  const PoseLookup quarter = buffer.interpolate(250);
  EXPECT_LT(quarter.pose.orientation.angularDistance(yaw(175.0 * deg)), 1e-9);
}

TEST(PoseBuffer, NeverExtrapolates) {
  PoseBuffer buffer(smallConfig());
  EXPECT_EQ(buffer.interpolate(0).coverage, PoseCoverage::kNotYet) << "empty buffer: wait";
  ASSERT_TRUE(buffer.insert(pose(1000, Eigen::Vector3d::Zero(), yaw(0))).accepted());
  ASSERT_TRUE(buffer.insert(pose(2000, Eigen::Vector3d::UnitX(), yaw(0))).accepted());
  EXPECT_EQ(buffer.interpolate(2001).coverage, PoseCoverage::kNotYet);
  EXPECT_EQ(buffer.interpolate(999).coverage, PoseCoverage::kTooOld);
  EXPECT_EQ(buffer.coverage(1000, 2000), PoseCoverage::kCovered);
  EXPECT_EQ(buffer.coverage(1500, 2500), PoseCoverage::kNotYet);
  EXPECT_EQ(buffer.coverage(500, 2500), PoseCoverage::kTooOld);
}

TEST(PoseBuffer, EvictsTheOldestPoseAtCapacity) {
  PoseBuffer buffer(smallConfig(3));
  for (std::int64_t t = 1; t <= 5; ++t) ASSERT_TRUE(buffer.insert(pose(t * 10, Eigen::Vector3d::Zero(), yaw(0))).accepted());
  EXPECT_EQ(buffer.size(), 3U);
  EXPECT_EQ(buffer.oldest().utime, 30);
  EXPECT_EQ(buffer.newest().utime, 50);
  EXPECT_EQ(buffer.counts().evicted, 2);
  EXPECT_EQ(buffer.interpolate(25).coverage, PoseCoverage::kTooOld);
  EXPECT_TRUE(buffer.interpolate(45).ok());
}

TEST(PoseBuffer, RejectsAndCountsBadPoses) {
  PoseBuffer buffer(smallConfig());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ASSERT_TRUE(buffer.insert(pose(1000, Eigen::Vector3d::Zero(), yaw(0))).accepted());
  EXPECT_EQ(buffer.insert(pose(1000, Eigen::Vector3d::UnitX(), yaw(0))).rejection, PoseRejection::kDuplicateTime);
  EXPECT_EQ(buffer.insert(pose(900, Eigen::Vector3d::UnitX(), yaw(0))).rejection, PoseRejection::kOutOfOrder);
  EXPECT_EQ(buffer.insert(pose(1100, {nan, 0, 0}, yaw(0))).rejection, PoseRejection::kNonFinite);
  EXPECT_EQ(buffer.insert(pose(1100, {0, 0, 0}, Eigen::Quaterniond(inf, 0, 0, 0))).rejection,
            PoseRejection::kNonFinite);
  EXPECT_EQ(buffer.insert(pose(1100, {0, 0, 0}, Eigen::Quaterniond(1.1, 0, 0, 0))).rejection,
            PoseRejection::kNotUnitQuaternion);
  EXPECT_EQ(buffer.insert(pose(1100, {0, 0, 0}, Eigen::Quaterniond(0, 0, 0, 0))).rejection,
            PoseRejection::kNotUnitQuaternion);
  const PoseBufferCounts& c = buffer.counts();
  EXPECT_EQ(c.accepted, 1);
  EXPECT_EQ(c.rejected_duplicate_time, 1);
  EXPECT_EQ(c.rejected_out_of_order, 1);
  EXPECT_EQ(c.rejected_non_finite, 2);
  EXPECT_EQ(c.rejected_not_unit, 2);
  EXPECT_EQ(c.rejected(), 6);
  EXPECT_EQ(buffer.size(), 1U);
}

TEST(PoseBuffer, NormalisesQuaternionsWithinTolerance) {
  PoseBuffer buffer(smallConfig());
  const PoseInsertResult r = buffer.insert(pose(10, Eigen::Vector3d::Zero(), Eigen::Quaterniond(1.0005, 0, 0, 0)));
  ASSERT_TRUE(r.accepted());
  EXPECT_TRUE(r.normalised);
  EXPECT_EQ(buffer.counts().normalised, 1);
  EXPECT_DOUBLE_EQ(buffer.newest().orientation.norm(), 1.0);
}

TEST(PoseBuffer, FlagsJumpsButKeepsThePose) {
  PoseBufferConfig c = smallConfig();
  c.jump_translation_m = 0.5;
  c.jump_rotation_rad = 0.2;
  PoseBuffer buffer(c);
  ASSERT_FALSE(buffer.insert(pose(10, Eigen::Vector3d::Zero(), yaw(0))).jump);
  EXPECT_FALSE(buffer.insert(pose(20, {0.4, 0, 0}, yaw(0.1))).jump);
  const PoseInsertResult moved = buffer.insert(pose(30, {1.0, 0, 0}, yaw(0.1)));
  EXPECT_TRUE(moved.accepted());
  EXPECT_TRUE(moved.jump);
  EXPECT_NEAR(moved.step_translation_m, 0.6, 1e-12);
  const PoseInsertResult turned = buffer.insert(pose(40, {1.0, 0, 0}, yaw(0.4)));
  EXPECT_TRUE(turned.jump);
  EXPECT_NEAR(turned.step_rotation_rad, 0.3, 1e-12);
  EXPECT_EQ(buffer.counts().jumps, 2);
  EXPECT_EQ(buffer.size(), 4U);
}

TEST(PoseBuffer, AJumpSplitsTheTrajectoryAndNothingIsInterpolatedAcrossIt) {
  PoseBuffer buffer(smallConfig());
  for (std::int64_t t = 0; t <= 100; t += 10) ASSERT_TRUE(buffer.insert(pose(t, {0.01 * static_cast<double>(t), 0, 0}, yaw(0))).accepted());
  const PoseInsertResult far = buffer.insert(pose(110, {1000.0, 0, 0}, yaw(0)));  // 1 km in 10 us
  ASSERT_TRUE(far.accepted());
  EXPECT_TRUE(far.jump);
  for (std::int64_t t = 120; t <= 200; t += 10) ASSERT_TRUE(buffer.insert(pose(t, {1000.0, 0, 0}, yaw(0))).accepted());
  // Each side of the split is whole; the split itself is never covered, waiting cannot change that.
  EXPECT_EQ(buffer.coverage(0, 100), PoseCoverage::kCovered);
  EXPECT_EQ(buffer.coverage(110, 200), PoseCoverage::kCovered);
  EXPECT_EQ(buffer.coverage(50, 150), PoseCoverage::kBroken);
  EXPECT_EQ(buffer.coverage(100, 110), PoseCoverage::kBroken);
  EXPECT_EQ(buffer.coverage(105, 105), PoseCoverage::kBroken);
  EXPECT_EQ(buffer.coverage(90, 500), PoseCoverage::kBroken) << "a span reaching past the newest pose is broken already";
  EXPECT_FALSE(buffer.interpolate(105).ok());
  EXPECT_EQ(buffer.interpolate(105).coverage, PoseCoverage::kBroken);
  EXPECT_TRUE(buffer.interpolate(100).ok());
  EXPECT_TRUE(buffer.interpolate(110).ok());
  EXPECT_EQ(buffer.interpolate(110).pose.position.x(), 1000.0);
  EXPECT_EQ(buffer.counts().jumps, 1);
}

TEST(PoseBuffer, ASplitLeavesWithTheOldestPose) {
  PoseBuffer buffer(smallConfig(4));
  ASSERT_TRUE(buffer.insert(pose(10, {0, 0, 0}, yaw(0))).accepted());
  ASSERT_TRUE(buffer.insert(pose(20, {50, 0, 0}, yaw(0))).jump);
  for (std::int64_t t = 30; t <= 60; t += 10) ASSERT_TRUE(buffer.insert(pose(t, {50, 0, 0}, yaw(0))).accepted());
  EXPECT_EQ(buffer.oldest().utime, 30);
  EXPECT_EQ(buffer.coverage(30, 60), PoseCoverage::kCovered);
}

TEST(PoseBuffer, RefusesAbsurdPositions) {
  PoseBuffer buffer(smallConfig());
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(1e300, 0, 0), Eigen::Vector3d(0, -2e7, 0), Eigen::Vector3d(0, 0, 1.1e7)}) {
    const PoseInsertResult r = buffer.insert(pose(10, p, yaw(0)));
    EXPECT_EQ(r.rejection, PoseRejection::kAbsurdPosition) << p.transpose();
  }
  EXPECT_EQ(buffer.counts().rejected_absurd, 3);
  EXPECT_EQ(buffer.counts().rejected(), 3);
  EXPECT_TRUE(buffer.empty());
  EXPECT_TRUE(buffer.insert(pose(10, {4.5e6, 5.8e6, 100}, yaw(0))).accepted()) << "UTM coordinates are not absurd";
}

TEST(PoseBuffer, ClearForgetsEveryPoseAndSplit) {
  PoseBuffer buffer(smallConfig());
  ASSERT_TRUE(buffer.insert(pose(1000, {0, 0, 0}, yaw(0))).accepted());
  ASSERT_TRUE(buffer.insert(pose(2000, {10, 0, 0}, yaw(0))).jump);
  buffer.clear();
  EXPECT_TRUE(buffer.empty());
  ASSERT_TRUE(buffer.insert(pose(10, {0, 0, 0}, yaw(0))).accepted()) << "an earlier time is accepted after clear()";
  ASSERT_TRUE(buffer.insert(pose(20, {0.1, 0, 0}, yaw(0))).accepted());
  EXPECT_EQ(buffer.coverage(10, 20), PoseCoverage::kCovered);
}

}  // namespace
}  // namespace ogf::fusion
