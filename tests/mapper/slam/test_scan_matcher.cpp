// The scan matcher on a synthetic room: it recovers a known pose offset (a large heading error with
// heading starts), its likelihood peaks at the true pose, and it reports an empty map as untrusted.
#include <gtest/gtest.h>

#include <cmath>
#include <ogf/slam/map_update.hpp>
#include <ogf/slam/scan_matcher.hpp>

#include "synthetic_room.hpp"

namespace ogf::slam {
namespace {

using testing::roomWalls;
using testing::scanAt;

TiledGrid mapFrom(const std::vector<Pose2>& poses) {
  TiledGrid grid(0.05);
  MapUpdateConfig update;
  for (const Pose2& p : poses) registerScan(grid, p, scanAt(roomWalls(), p), update);
  return grid;
}

TEST(ScanMatcher, RecoversAKnownOffsetInASyntheticRoom) {
  const TiledGrid grid = mapFrom({{3.0, 3.0, 0.0}, {4.0, 4.0, 0.5}});
  const ScanMatcher matcher(ScanMatcherConfig{});
  const Pose2 truth{3.6, 3.4, 0.2};
  const PreparedScan scan = matcher.prepare(scanAt(roomWalls(), truth), grid.resolution());
  const Pose2 start{truth.x + 0.12, truth.y - 0.09, truth.theta + 0.06};
  const MatchResult m = matcher.match(grid, start, scan, nullptr);
  EXPECT_TRUE(m.converged);
  EXPECT_NEAR(m.pose.x, truth.x, 0.02);
  EXPECT_NEAR(m.pose.y, truth.y, 0.02);
  EXPECT_NEAR(m.pose.theta, truth.theta, 0.01);
  EXPECT_GT(m.objective, matcher.likelihood(grid, start, scan).log_likelihood);
}

TEST(ScanMatcher, HeadingStartsRecoverAHeadingErrorOneClimbDoesNot) {
  const TiledGrid grid = mapFrom({{3.0, 3.0, 0.0}, {4.0, 4.0, 0.5}});
  const Pose2 truth{3.6, 3.4, 0.2};
  const ScanMatcher single(ScanMatcherConfig{});
  const PreparedScan scan = single.prepare(scanAt(roomWalls(), truth), grid.resolution());
  ScanMatcherConfig several;
  several.heading_starts = 3;
  several.heading_start_step_rad = 0.15;
  const ScanMatcher multi(several);
  // 0.5 rad off: one climb ends on a wrong local maximum; a start 0.45 rad back finds the true pose.
  const Pose2 start{truth.x, truth.y, truth.theta - 0.5};
  const MatchResult one = single.match(grid, start, scan, nullptr);
  EXPECT_GT(std::abs(one.pose.theta - truth.theta), 0.1);
  const MatchResult m = multi.match(grid, start, scan, nullptr);
  EXPECT_TRUE(m.converged);
  EXPECT_NEAR(m.pose.x, truth.x, 0.02);
  EXPECT_NEAR(m.pose.y, truth.y, 0.02);
  EXPECT_NEAR(m.pose.theta, truth.theta, 0.01);
  EXPECT_GT(m.objective, one.objective);
  EXPECT_GT(m.evaluations, one.evaluations);
}

TEST(ScanMatcher, LikelihoodIsHighestAtTheTruePose) {
  const TiledGrid grid = mapFrom({{3.0, 3.0, 0.0}});
  const ScanMatcher matcher(ScanMatcherConfig{});
  const Pose2 truth{3.0, 3.0, 0.0};
  const PreparedScan scan = matcher.prepare(scanAt(roomWalls(), truth), grid.resolution());
  const ScanLikelihood at_truth = matcher.likelihood(grid, truth, scan);
  EXPECT_GT(at_truth.matchedFraction(), 0.5);  // grazing beams find their free probe occupied
  for (const Pose2& off : {Pose2{3.1, 3.0, 0.0}, Pose2{3.0, 2.9, 0.0}, Pose2{3.0, 3.0, 0.05}}) {
    EXPECT_LT(matcher.likelihood(grid, off, scan).log_likelihood, at_truth.log_likelihood);
  }
}

TEST(ScanMatcher, MotionPriorPullsTheMatchTowardsThePrediction) {
  const TiledGrid grid = mapFrom({{3.0, 3.0, 0.0}});
  ScanMatcherConfig config;
  const ScanMatcher matcher(config);
  const Pose2 truth{3.0, 3.0, 0.0};
  const PreparedScan scan = matcher.prepare(scanAt(roomWalls(), truth), grid.resolution());
  // A prior far tighter than the map: the maximum stays near the prediction.
  MotionGaussian prior;
  prior.previous = {2.0, 3.0, 0.0};
  prior.step = {1.1, 0.0, 0.0};
  prior.sigma_x = prior.sigma_y = 0.0005;
  prior.sigma_theta = 0.0005;
  const MatchResult m = matcher.match(grid, {3.1, 3.0, 0.0}, scan, &prior);
  EXPECT_NEAR(m.pose.x, 3.1, 0.01);
}

TEST(ScanMatcher, AnEmptyMapGivesAnUntrustedMatch) {
  const TiledGrid grid(0.05);
  const ScanMatcher matcher(ScanMatcherConfig{});
  const PreparedScan scan = matcher.prepare(scanAt(roomWalls(), {3, 3, 0}), grid.resolution());
  EXPECT_FALSE(matcher.match(grid, {3, 3, 0}, scan, nullptr).converged);
}

TEST(ScanMatcher, NoReturnAndLongBeamsAreNotMatched) {
  ScanMatcherConfig config;
  config.usable_range_m = 5.0;
  const ScanMatcher matcher(config);
  PlanarScan scan;
  scan.angle_increment_rad = 0.1;
  scan.max_range_m = 10.0;
  scan.ranges_m = {1.0F, 10.0F, 6.0F, 0.0F, 2.0F};
  EXPECT_EQ(matcher.prepare(scan, 0.05).beams.size(), 2U);
}

TEST(ScanMatcher, ConfigValidationNamesTheField) {
  ScanMatcherConfig config;
  config.beam_stride = 0;
  const Status s = config.validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("beam_stride"), std::string::npos);
  ScanMatcherConfig starts;
  starts.heading_starts = -1;
  ASSERT_FALSE(starts.validate().ok());
  EXPECT_NE(starts.validate().error().message.find("heading_starts"), std::string::npos);
}

}  // namespace
}  // namespace ogf::slam
