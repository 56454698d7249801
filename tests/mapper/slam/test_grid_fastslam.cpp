// Grid-based FastSLAM on a synthetic room with drifting odometry: it corrects the drift, it is
// deterministic for a seed, particles share map tiles, and the PoseCorrector's modes behave.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <ogf/slam/grid_fastslam.hpp>
#include <ogf/slam/pose_corrector.hpp>
#include <vector>

#include "synthetic_room.hpp"

namespace ogf::slam {
namespace {

using testing::roomWalls;
using testing::scanAt;

// A loop around the room's free space; odometry over-reads every step by 5 % and turns 0.02 rad too
// little per metre, so it drifts.
struct Drive {
  std::vector<Pose2> truth;
  std::vector<Pose2> odometry;
};

Drive driveAroundTheRoom() {
  Drive d;
  const std::vector<Pose2> corners{
      {1.2, 1.0, 0.0}, {4.5, 1.0, 0.0}, {4.5, 4.6, 0.0}, {1.2, 4.6, 0.0}, {1.2, 1.0, 0.0}};
  for (std::size_t c = 0; c + 1 < corners.size(); ++c) {
    const Pose2 a = corners[c], b = corners[c + 1];
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    const int steps = static_cast<int>(std::hypot(b.x - a.x, b.y - a.y) / 0.1);
    for (int i = 0; i < steps; ++i) {
      const double f = static_cast<double>(i) / steps;
      d.truth.push_back({a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), heading});
    }
  }
  Pose2 odo = d.truth.front();
  d.odometry.push_back(odo);
  for (std::size_t i = 1; i < d.truth.size(); ++i) {
    Pose2 step = between(d.truth[i - 1], d.truth[i]);
    step.x *= 1.05;
    step.y *= 1.05;
    step.theta -= 0.02 * translationNorm(step) + 0.03 * step.theta;
    odo = compose(odo, step);
    d.odometry.push_back(odo);
  }
  return d;
}

double finalError(const std::vector<Pose2>& estimate, const std::vector<Pose2>& truth) {
  // Both start at the same pose, so the last pose's distance measures the accumulated drift.
  return std::hypot(estimate.back().x - truth.back().x, estimate.back().y - truth.back().y);
}

std::vector<Pose2> run(PoseCorrectorConfig config, const Drive& d) {
  auto corrector = PoseCorrector::create(config);
  EXPECT_TRUE(corrector.ok());
  for (std::size_t i = 0; i < d.truth.size(); ++i)
    (void)corrector->correct(d.odometry[i], scanAt(roomWalls(), d.truth[i], 180));
  return corrector->correctedTrajectory(d.odometry);
}

PoseCorrectorConfig smallConfig(CorrectionMode mode) {
  PoseCorrectorConfig c;
  c.mode = mode;
  c.slam.particles = 8;
  c.slam.linear_update_m = 0.3;
  return c;
}

TEST(GridFastSlam, ScanMatchingAndRbpfCorrectOdometryDrift) {
  const Drive d = driveAroundTheRoom();
  const double odometry_error = finalError(d.odometry, d.truth);
  ASSERT_GT(odometry_error, 0.5);
  const double sm = finalError(run(smallConfig(CorrectionMode::kScanMatch), d), d.truth);
  const double rbpf = finalError(run(smallConfig(CorrectionMode::kRbpf), d), d.truth);
  EXPECT_LT(sm, 0.1) << "odometry " << odometry_error;
  EXPECT_LT(rbpf, 0.1) << "odometry " << odometry_error;
}

TEST(GridFastSlam, ModeNonePassesOdometryThrough) {
  const Drive d = driveAroundTheRoom();
  const std::vector<Pose2> out = run(smallConfig(CorrectionMode::kNone), d);
  EXPECT_DOUBLE_EQ(out.back().x, d.odometry.back().x);
}

TEST(GridFastSlam, SameSeedSameTrajectoryOtherSeedOtherTrajectory) {
  const Drive d = driveAroundTheRoom();
  PoseCorrectorConfig c = smallConfig(CorrectionMode::kRbpf);
  const std::vector<Pose2> a = run(c, d), b = run(c, d);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x) << i;
    EXPECT_EQ(a[i].theta, b[i].theta) << i;
  }
  c.slam.seed = 4242;
  const std::vector<Pose2> other = run(c, d);
  bool differs = false;
  for (std::size_t i = 0; i < a.size(); ++i) differs = differs || a[i].x != other[i].x;
  EXPECT_TRUE(differs);
}

TEST(GridFastSlam, ParticlesShareTheTilesTheyHaveNotChanged) {
  const Drive d = driveAroundTheRoom();
  GridFastSlamConfig c;
  c.particles = 10;
  c.linear_update_m = 0.3;
  auto slam = GridFastSlam::create(c);
  ASSERT_TRUE(slam.ok());
  // The first scan: every particle holds the same map, tile for tile.
  slam->addScan(0, d.odometry[0], scanAt(roomWalls(), d.truth[0], 180));
  const auto& ps = slam->particles();
  const std::size_t tiles = ps[0].map.allocatedTiles();
  for (const Particle& p : ps) EXPECT_EQ(p.map.sharedTilesWith(ps[0].map), tiles);
  for (std::size_t i = 1; i < d.truth.size(); ++i)
    slam->addScan(i, d.odometry[i], scanAt(roomWalls(), d.truth[i], 180));
  // Total distinct tiles stays far below particles × tiles per map.
  std::size_t unique = 0;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    std::size_t shared_with_earlier = 0;
    for (std::size_t j = 0; j < i; ++j)
      shared_with_earlier = std::max(shared_with_earlier, ps[i].map.sharedTilesWith(ps[j].map));
    unique += ps[i].map.allocatedTiles() - shared_with_earlier;
  }
  EXPECT_LT(unique, ps.size() * ps[0].map.allocatedTiles());
  EXPECT_GT(slam->statistics().scans_processed, 10U);
}

TEST(GridFastSlam, ScansBetweenProcessedOnesAreMatchedAgainstTheBestMap) {
  const Drive d = driveAroundTheRoom();
  GridFastSlamConfig c;
  c.particles = 4;
  c.linear_update_m = 0.5;
  auto slam = GridFastSlam::create(c);
  ASSERT_TRUE(slam.ok());
  for (std::size_t i = 0; i < d.truth.size(); ++i)
    slam->addScan(i, d.odometry[i], scanAt(roomWalls(), d.truth[i], 180));
  const auto& skipped = slam->skippedScanPoses();
  ASSERT_GT(skipped.size(), d.truth.size() / 2);
  // Every skipped scan's pose with hindsight is near the truth, though odometry alone drifts.
  const std::vector<TrajectoryPoint> points = slam->bestTrajectory();
  double worst = 0.0;
  for (const SkippedScanPose& s : skipped) {
    const Pose2 p = slam->poseWithHindsight(points, s.scan_id, d.odometry[s.scan_id]);
    worst = std::max(worst, std::hypot(p.x - d.truth[s.scan_id].x, p.y - d.truth[s.scan_id].y));
  }
  EXPECT_LT(worst, 0.1);
}

TEST(GridFastSlam, WeightUnmatchedDistanceChangesTheWeightsNotTheMatch) {
  const Drive d = driveAroundTheRoom();
  const auto drive = [&d](double weight_unmatched_m) {
    GridFastSlamConfig c;
    c.particles = 4;
    c.linear_update_m = 0.3;
    c.weight_unmatched_distance_m = weight_unmatched_m;
    auto slam = GridFastSlam::create(c);
    EXPECT_TRUE(slam.ok());
    for (std::size_t i = 0; i < 20; ++i)
      slam->addScan(i, d.odometry[i], scanAt(roomWalls(), d.truth[i], 180));
    return slam->particles();
  };
  // 0 takes the matcher's distance: the same run as naming that distance.
  const std::vector<Particle> none = drive(0.0),
                              same = drive(GridFastSlamConfig{}.matcher.unmatched_distance_m);
  const std::vector<Particle> costly = drive(0.4);
  double lowest_none = 0.0, highest_costly = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < none.size(); ++i) {
    EXPECT_EQ(none[i].log_weight_total, same[i].log_weight_total) << i;
    lowest_none = std::min(lowest_none, none[i].log_weight_total);
    highest_costly = std::max(highest_costly, costly[i].log_weight_total);
  }
  // Unmatched beams (grazing ones, walls seen for the first time) cost more: every weight drops.
  EXPECT_LT(highest_costly, lowest_none);
  GridFastSlamConfig bad;
  bad.weight_unmatched_distance_m = -1.0;
  ASSERT_FALSE(bad.validate().ok());
  EXPECT_NE(bad.validate().error().message.find("weight_unmatched_distance_m"), std::string::npos);
}

TEST(GridFastSlam, ConfigValidationNamesTheNestedField) {
  GridFastSlamConfig c;
  c.proposal.samples_per_axis = 0;
  const Status s = c.validate();
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("proposal.samples_per_axis"), std::string::npos) << s.error().message;
  EXPECT_FALSE(GridFastSlam::create(c).ok());
  EXPECT_FALSE(parseCorrectionMode("gmapping").ok());
  EXPECT_EQ(*parseCorrectionMode("scan-match"), CorrectionMode::kScanMatch);
}

}  // namespace
}  // namespace ogf::slam
