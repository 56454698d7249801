// The correction stage on a synthetic room seen by a 3-D lidar: with drifting odometry, scan matching puts
// the scans back near the true poses; mode none leaves them where odometry put them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "ogf/correction/planar_pose.hpp"
#include "ogf/correction/scan_pose_correction.hpp"

namespace oc = ogf::correction;
namespace os = ogf::slam;

namespace {

// Distance along a ray from (px, py) in direction (dx, dy) to the nearest wall of a 10 m x 7 m room with
// two pillars (so no direction along the room is unobservable).
double rangeInRoom(double px, double py, double dx, double dy) {
  struct Box {
    double x0, y0, x1, y1;
  };
  const Box pillars[] = {{1.0, 1.0, 1.6, 1.6}, {3.0, -2.0, 3.4, -1.2}};
  double best = std::numeric_limits<double>::infinity();
  // Inside the room: the exit distance through the walls x in [-4, 6], y in [-3, 4].
  if (dx > 0) best = std::min(best, (6.0 - px) / dx);
  if (dx < 0) best = std::min(best, (-4.0 - px) / dx);
  if (dy > 0) best = std::min(best, (4.0 - py) / dy);
  if (dy < 0) best = std::min(best, (-3.0 - py) / dy);
  for (const Box& b : pillars) {  // slab test
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    const double lo[2] = {b.x0, b.y0}, hi[2] = {b.x1, b.y1}, p[2] = {px, py}, d[2] = {dx, dy};
    bool hit = true;
    for (int a = 0; a < 2 && hit; ++a) {
      if (std::abs(d[a]) < 1e-12) {
        hit = p[a] >= lo[a] && p[a] <= hi[a];
        continue;
      }
      double ta = (lo[a] - p[a]) / d[a], tb = (hi[a] - p[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      hit = t0 <= t1;
    }
    if (hit && t0 > 0.0) best = std::min(best, t0);
  }
  return best;
}

// The scan in the body frame at the true planar pose: 720 bearings, three rings of heights in the band.
std::vector<Eigen::Vector3d> bodyScan(const os::Pose2& truth) {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 720; ++i) {
    const double b = -std::numbers::pi + (i + 0.5) * (2.0 * std::numbers::pi / 720.0);
    const double r = rangeInRoom(truth.x, truth.y, std::cos(truth.theta + b), std::sin(truth.theta + b));
    for (double z : {0.3, 0.8, 1.2}) points.emplace_back(r * std::cos(b), r * std::sin(b), z);
  }
  return points;
}

struct DriftRun {
  double final_error_odometry = 0.0;
  double final_error_corrected = 0.0;
};

DriftRun driveThroughTheRoom(os::CorrectionMode mode) {
  oc::ScanPoseCorrectionConfig config;
  config.corrector.mode = mode;
  auto correction = oc::ScanPoseCorrection::create(config);
  EXPECT_TRUE(correction) << correction.error().message;
  os::Pose2 truth{-2.5, 0.5, 0.0}, odometry = truth;
  Eigen::Isometry3d map_from_body = Eigen::Isometry3d::Identity();
  for (int k = 0; k < 24; ++k) {
    if (k > 0) {  // the robot drives 0.25 m and turns a little; odometry over-reads by 6 % and 0.03 rad
      const os::Pose2 step{0.25, 0.0, 0.02};
      truth = os::compose(truth, step);
      odometry = os::compose(odometry, os::Pose2{0.25 * 1.06, 0.0, 0.02 + 0.03});
    }
    const Eigen::Isometry3d odom_from_body = oc::liftPlanarPose(odometry);
    std::vector<Eigen::Vector3d> endpoints;
    for (const auto& p : bodyScan(truth)) endpoints.push_back(odom_from_body * p);
    const oc::ScanCorrection c = correction->correct(odom_from_body, endpoints);
    map_from_body = c.map_from_body;
    if (mode != os::CorrectionMode::kNone) {
      EXPECT_GT(c.planar_beams_used, 300u) << "scan " << k;
    }
  }
  const os::Pose2 corrected = oc::planarPoseOf(map_from_body);
  return {std::hypot(odometry.x - truth.x, odometry.y - truth.y), std::hypot(corrected.x - truth.x, corrected.y - truth.y)};
}

}  // namespace

TEST(ScanPoseCorrection, ModeNoneLeavesOdometryAsItIs) {
  const DriftRun run = driveThroughTheRoom(os::CorrectionMode::kNone);
  EXPECT_GT(run.final_error_odometry, 0.5);
  EXPECT_DOUBLE_EQ(run.final_error_corrected, run.final_error_odometry);
}

TEST(ScanPoseCorrection, ScanMatchingUndoesMostOfTheOdometryDrift) {
  const DriftRun run = driveThroughTheRoom(os::CorrectionMode::kScanMatch);
  EXPECT_GT(run.final_error_odometry, 0.5);
  EXPECT_LT(run.final_error_corrected, 0.15) << "odometry error " << run.final_error_odometry;
}

TEST(ScanPoseCorrection, AnInvalidConfigurationNamesTheField) {
  oc::ScanPoseCorrectionConfig config;
  config.corrector.mode = os::CorrectionMode::kScanMatch;
  config.projection.z_max_m = -1.0;
  const auto c = oc::ScanPoseCorrection::create(config);
  ASSERT_FALSE(c);
  EXPECT_NE(c.error().message.find("projection."), std::string::npos) << c.error().message;
}
