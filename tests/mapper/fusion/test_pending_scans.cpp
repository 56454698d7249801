// PendingScans: scans leave once covered, in arrival order; waiting is bounded in time; the queue is
// bounded in scans and points by dropping the oldest whole scan; every drop is counted.
#include <ogf/fusion/pending_scans.hpp>

#include <gtest/gtest.h>

#include <memory>

namespace ogf::fusion {
namespace {

PendingScansConfig pendingConfig(double wait_s = 0.2, std::size_t scans = 4, std::size_t points = 1000) {
  PendingScansConfig c;
  c.max_pose_wait_s = wait_s;
  c.max_pending_scans = scans;
  c.max_pending_points = points;
  return c;
}

PoseBuffer posesUntil(std::int64_t from, std::int64_t to) {
  PoseBuffer buffer(PoseBufferConfig{});
  for (std::int64_t t = from; t <= to; t += 10'000) {
    EXPECT_TRUE(buffer.insert({t, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()}).accepted());
  }
  return buffer;
}

ScanSpan scan(std::int64_t begin, std::size_t points = 100) { return {begin, begin + 99'000, points}; }

const PoseBuffer kNoPoses{PoseBufferConfig{}};

TEST(PendingScans, ScanLeavesOnlyOnceItsWholeSpanIsCovered) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(1'000'000), 7, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_FALSE(pending.popReady(posesUntil(900'000, 1'050'000), 10'000)) << "half covered: wait";
  EXPECT_EQ(pending.size(), 1U);
  const auto ready = pending.popReady(posesUntil(900'000, 1'100'000), 20'000);
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->payload, 7);
  EXPECT_EQ(pending.size(), 0U);
  EXPECT_EQ(pending.points(), 0U);
}

TEST(PendingScans, ScanWaitingLongerThanMaxWaitIsDroppedAndCounted) {
  PendingScans<int> pending(pendingConfig(0.2));
  ASSERT_EQ(pending.push(scan(1'000'000), 1, kNoPoses, 5'000'000), PushOutcome::kQueued);
  const PoseBuffer poses = posesUntil(900'000, 1'050'000);
  EXPECT_FALSE(pending.popReady(poses, 5'200'000)) << "exactly max wait: still waiting";
  EXPECT_EQ(pending.size(), 1U);
  EXPECT_FALSE(pending.popReady(poses, 5'200'001));
  EXPECT_EQ(pending.size(), 0U);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 1);
}

TEST(PendingScans, ScanOlderThanTheOldestPoseIsDroppedAtOnce) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(1'000'000), 1, kNoPoses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(2'000'000), 2, kNoPoses, 0), PushOutcome::kQueued);
  const auto ready = pending.popReady(posesUntil(1'500'000, 2'200'000), 0);
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->payload, 2);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 1);
}

TEST(PendingScans, ScansLeaveInArrivalOrder) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(1'000'000), 1, kNoPoses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(1'100'000), 2, kNoPoses, 0), PushOutcome::kQueued);
  const PoseBuffer poses = posesUntil(900'000, 1'300'000);
  EXPECT_EQ(pending.popReady(poses, 0)->payload, 1);
  EXPECT_EQ(pending.popReady(poses, 0)->payload, 2);
  EXPECT_FALSE(pending.popReady(poses, 0));
}

TEST(PendingScans, FullQueueDropsTheOldestWholeScanAsBehindWhenItsPosesHadArrived) {
  PendingScans<std::shared_ptr<int>> pending(pendingConfig(1.0, 3, 1000));
  const PoseBuffer poses = posesUntil(0, 2'000'000);
  auto first = std::make_shared<int>(0);
  ASSERT_EQ(pending.push(scan(1'000'000), first, poses, 0), PushOutcome::kQueued);
  for (int i = 1; i < 5; ++i) {
    ASSERT_EQ(pending.push(scan(1'000'000 + i * 100'000), std::make_shared<int>(i), poses, 0), PushOutcome::kQueued);
  }
  EXPECT_EQ(pending.size(), 3U);
  EXPECT_EQ(pending.counts().scans_dropped_behind, 2);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 0);
  EXPECT_EQ(first.use_count(), 1) << "the dropped payload is released";
  EXPECT_EQ(*pending.popReady(poses, 0)->payload, 2);
}

// Scans arrive and no odometry does: the queue fills and every scan pushed out was waiting for its poses.
TEST(PendingScans, AScanPushedOutWhileItsPosesHaveNotArrivedIsDroppedForWantOfAPoseNotBehind) {
  PendingScans<int> pending(pendingConfig(1.0, 3, 1000));
  for (int i = 0; i < 10; ++i) ASSERT_EQ(pending.push(scan(1'000'000 + i * 100'000), i, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 7);
  EXPECT_EQ(pending.counts().scans_dropped_behind, 0);
  // Odometry that stops before the scans: the scans beyond its newest pose are still waiting for it.
  PendingScans<int> lagging(pendingConfig(1.0, 3, 1000));
  const PoseBuffer poses = posesUntil(0, 1'250'000);
  for (int i = 0; i < 6; ++i) ASSERT_EQ(lagging.push(scan(1'000'000 + i * 100'000), i, poses, 0), PushOutcome::kQueued);
  EXPECT_EQ(lagging.counts().scans_dropped_behind, 2) << "scans 0 and 1 were covered: the mapper was behind";
  EXPECT_EQ(lagging.counts().scans_dropped_no_pose, 1) << "scan 2 ends after the newest pose";
}

TEST(PendingScans, PopOldestTakesTheScansInArrivalOrderWithoutPoses) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(1'000'000, 300), 1, kNoPoses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(1'100'000, 200), 2, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_EQ(pending.popOldest()->payload, 1);
  EXPECT_EQ(pending.points(), 200U);
  EXPECT_EQ(pending.popOldest()->payload, 2);
  EXPECT_FALSE(pending.popOldest());
  EXPECT_EQ(pending.points(), 0U);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose + pending.counts().scans_dropped_behind, 0);
}

// A sensor whose pose is fixed waits for no odometry: a scan pushed out of a full queue could have been
// mapped, so the mapper was behind, by scans and by points alike.
TEST(PendingScans, WithAFixedPoseAScanPushedOutIsDroppedBehindNotForWantOfAPose) {
  PendingScans<int> pending(pendingConfig(1.0, 3, 1000));
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(pending.pushFixedPose(scan(1'000'000 + i * 100'000), i, 0), PushOutcome::kQueued);
  }
  EXPECT_EQ(pending.counts().scans_dropped_behind, 7);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 0);
  EXPECT_EQ(pending.popOldest()->payload, 7);
  ASSERT_EQ(pending.pushFixedPose(scan(2'000'000, 900), 10, 0), PushOutcome::kQueued);  // 200 + 900 > 1000
  EXPECT_EQ(pending.counts().scans_dropped_behind, 8);
  EXPECT_EQ(pending.pushFixedPose(scan(2'100'000, 1001), 11, 0), PushOutcome::kTooLarge);
  EXPECT_EQ(pending.counts().scans_dropped_behind, 9);
  EXPECT_EQ(pending.counts().scans_in, 12);
  EXPECT_EQ(pending.pushFixedPose(scan(2'000'000), 12, 0), PushOutcome::kLate);
}

TEST(PendingScans, PointBoundDropsOldestScansUntilTheNewOneFits) {
  PendingScans<int> pending(pendingConfig(1.0, 10, 1000));
  const PoseBuffer poses = posesUntil(0, 2'000'000);
  ASSERT_EQ(pending.push(scan(1'000'000, 400), 1, poses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(1'100'000, 400), 2, poses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(1'200'000, 500), 3, poses, 0), PushOutcome::kQueued);  // 1300 > 1000: drop one
  EXPECT_EQ(pending.points(), 900U);
  EXPECT_EQ(pending.counts().scans_dropped_behind, 1);
  EXPECT_EQ(pending.push(scan(1'300'000, 1001), 4, poses, 0), PushOutcome::kTooLarge);
  EXPECT_EQ(pending.counts().scans_dropped_behind, 2);
  EXPECT_EQ(pending.size(), 2U);
}

TEST(PendingScans, LateAndMalformedScansAreRefusedAndCounted) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(2'000'000), 1, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_EQ(pending.push(scan(1'000'000), 2, kNoPoses, 0), PushOutcome::kLate);
  EXPECT_EQ(pending.push(scan(2'000'000), 3, kNoPoses, 0), PushOutcome::kLate) << "a duplicate is late too";
  EXPECT_EQ(pending.push({3'000'000, 2'999'999, 10}, 4, kNoPoses, 0), PushOutcome::kRejected);
  EXPECT_EQ(pending.counts().scans_in, 4);
  EXPECT_EQ(pending.counts().scans_late, 2);
  EXPECT_EQ(pending.counts().scans_rejected, 1);
  EXPECT_EQ(pending.size(), 1U);
}

TEST(PendingScans, AScanSpanningAPoseJumpIsDroppedAndCountedAndTheNextIsMapped) {
  PendingScans<int> pending(pendingConfig());
  PoseBuffer poses(PoseBufferConfig{});
  for (std::int64_t t = 900'000; t <= 1'300'000; t += 10'000) {
    const double x = t < 1'050'000 ? 0.0 : 1000.0;  // 1 km between 1.04 s and 1.05 s
    ASSERT_TRUE(poses.insert({t, Eigen::Vector3d(x, 0, 0), Eigen::Quaterniond::Identity()}).accepted());
  }
  ASSERT_EQ(pending.push(scan(1'000'000), 1, kNoPoses, 0), PushOutcome::kQueued);
  ASSERT_EQ(pending.push(scan(1'100'000), 2, kNoPoses, 0), PushOutcome::kQueued);
  const auto ready = pending.popReady(poses, 0);
  ASSERT_TRUE(ready);
  EXPECT_EQ(ready->payload, 2);
  EXPECT_EQ(pending.counts().scans_dropped_pose_jump, 1);
  EXPECT_EQ(pending.counts().scans_dropped_no_pose, 0);
}

TEST(PendingScans, AfterAClockRestartAnEarlierScanIsNotLate) {
  PendingScans<int> pending(pendingConfig());
  ASSERT_EQ(pending.push(scan(5'000'000), 1, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_EQ(pending.push(scan(1'000'000), 2, kNoPoses, 0), PushOutcome::kLate);
  pending.restartClock();
  EXPECT_EQ(pending.push(scan(1'000'000), 3, kNoPoses, 0), PushOutcome::kQueued);
  EXPECT_EQ(pending.counts().scans_late, 1);
}

}  // namespace
}  // namespace ogf::fusion
