// The absolute trajectory error on trajectories with errors computed by hand: exact stamps, a stamp between
// two true samples (interpolated), stamps outside the truth or across a gap left unmatched, and RMSE, mean
// and max of known distances.
#include <gtest/gtest.h>

#include <cmath>

#include "ogf/eval/trajectory_error.hpp"

namespace {

using ogf::eval::absoluteTrajectoryError;
using ogf::sim::StampedPose;

StampedPose at(std::int64_t utime, double x, double y) {
  StampedPose p;
  p.utime = utime;
  p.pose.position = Eigen::Vector3d(x, y, 0.0);
  return p;
}

// The truth drives along x at 1 m/s, sampled every 0.1 s.
std::vector<StampedPose> straightTruth() {
  std::vector<StampedPose> t;
  for (int i = 0; i <= 10; ++i) t.push_back(at(i * 100'000, 0.1 * i, 0.0));
  return t;
}

TEST(AbsoluteTrajectoryError, TheTruthItselfScoresZero) {
  const auto truth = straightTruth();
  const auto e = absoluteTrajectoryError(truth, truth);
  EXPECT_EQ(e.matched, truth.size());
  EXPECT_EQ(e.unmatched, 0u);
  EXPECT_DOUBLE_EQ(e.rmse_m, 0.0);
  EXPECT_DOUBLE_EQ(e.max_m, 0.0);
}

TEST(AbsoluteTrajectoryError, RmseMeanAndMaxOfKnownDistances) {
  // Errors 0, 0.3 (a 3-4-5 offset scaled by 0.1: 0.5) and 0.3 m.
  const auto e = absoluteTrajectoryError(straightTruth(),
                                         {at(0, 0.0, 0.0), at(100'000, 0.4, 0.4), at(200'000, 0.2, 0.3)});
  EXPECT_EQ(e.matched, 3u);
  EXPECT_NEAR(e.mean_m, (0.0 + 0.5 + 0.3) / 3.0, 1e-12);
  EXPECT_NEAR(e.rmse_m, std::sqrt((0.25 + 0.09) / 3.0), 1e-12);
  EXPECT_NEAR(e.max_m, 0.5, 1e-12);
}

TEST(AbsoluteTrajectoryError, AStampBetweenTrueSamplesIsInterpolated) {
  // At 0.25 s the truth is at x = 0.25; the estimate at (0.25, 0.1) is 0.1 m off, not 0.05 or more.
  const auto e = absoluteTrajectoryError(straightTruth(), {at(250'000, 0.25, 0.1)});
  EXPECT_EQ(e.matched, 1u);
  EXPECT_NEAR(e.mean_m, 0.1, 1e-12);
}

TEST(AbsoluteTrajectoryError, StampsOutsideTheTruthOrAcrossAGapAreUnmatched) {
  auto truth = straightTruth();
  truth.push_back(at(5'000'000, 5.0, 0.0));  // a 4 s gap after 1 s
  const auto e = absoluteTrajectoryError(
      truth, {at(-1, 0, 0), at(2'000'000, 2.0, 0.0), at(6'000'000, 6.0, 0.0), at(5'000'000, 5.0, 1.0)});
  EXPECT_EQ(e.unmatched, 3u);
  EXPECT_EQ(e.matched, 1u);
  EXPECT_NEAR(e.max_m, 1.0, 1e-12);
}

}  // namespace
