// Odometry outputs: exact by default, drifting with an error preset (the drift presets by the magnitudes
// they document), and the CSV and the LCM log agree.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "ogf/sim/odometry_error.hpp"
#include "ogf/sim/pose_files.hpp"
#include "sim_test_paths.hpp"

namespace ogf::sim {
namespace {

std::vector<StampedPose> truthAlongLoop(double seconds) {
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}, {8, 0, 0}, {8, 5, 0}, {0, 5, 0}}, 1.0, true, 0.0});
  std::vector<StampedPose> out;
  for (std::int64_t u = 0; u <= static_cast<std::int64_t>(seconds * 1e6); u += 10000) {
    out.push_back({1704110400000000LL + u, traj->poseAt(static_cast<double>(u) * 1e-6)});
  }
  return out;
}

std::string tempPath(const std::string& name) {
  return test::scratchPath(name).string();
}

TEST(SimOdometry, NonePresetReproducesTheTruth) {
  const auto truth = truthAlongLoop(5.0);
  const auto model = odometryErrorPreset("none");
  ASSERT_TRUE(model.ok());
  const auto odom = simulateOdometry(truth, *model, 1);
  ASSERT_EQ(odom.size(), truth.size());
  for (std::size_t i = 0; i < odom.size(); ++i) {
    EXPECT_EQ(odom[i].utime, truth[i].utime);
    EXPECT_EQ(odom[i].pose.position, truth[i].pose.position);
  }
}

TEST(SimOdometry, WheelPresetDriftsMoreTheFartherItGoes) {
  const auto truth = truthAlongLoop(25.0);
  const auto model = odometryErrorPreset("wheel");
  ASSERT_TRUE(model.ok());
  const auto odom = simulateOdometry(truth, *model, 7);
  ASSERT_EQ(odom.size(), truth.size());
  EXPECT_LT((odom.front().pose.position - truth.front().pose.position).norm(), 0.02);
  const double early = (odom[200].pose.position - truth[200].pose.position).norm();    // 2 m driven
  const double late = (odom.back().pose.position - truth.back().pose.position).norm();  // 25 m driven
  EXPECT_GT(late, 0.05);
  EXPECT_GT(late, early);
  // Deterministic for a seed, different for another.
  EXPECT_EQ(simulateOdometry(truth, *model, 7).back().pose.position, odom.back().pose.position);
  EXPECT_NE(simulateOdometry(truth, *model, 8).back().pose.position, odom.back().pose.position);
}

// Heading (yaw about +z) of a pose, radians.
double yawOf(const Pose& p) {
  const Eigen::Matrix3d r = p.orientation.toRotationMatrix();
  return std::atan2(r(1, 0), r(0, 0));
}

double headingError(const StampedPose& odom, const StampedPose& truth) {
  return std::remainder(yawOf(odom.pose) - yawOf(truth.pose), 2.0 * M_PI);
}

TEST(SimOdometryDrift, GyroBiasTurnsTheHeadingByTheBiasTimesTheTime) {
  const auto truth = truthAlongLoop(25.0);
  const auto model = odometryErrorPreset("gyro-bias");
  ASSERT_TRUE(model.ok());
  const auto odom = simulateOdometry(truth, *model, 3);
  ASSERT_EQ(odom.size(), truth.size());
  for (std::size_t i = 0; i < odom.size(); i += 100) {
    const double t = static_cast<double>(truth[i].utime - truth.front().utime) * 1e-6;
    EXPECT_NEAR(headingError(odom[i], truth[i]), 0.0035 * t, 1e-9) << "t = " << t;
  }
  // The heading error bends the path: after 25 s (up to 5 degrees off) the end is decimetres away.
  EXPECT_GT((odom.back().pose.position - truth.back().pose.position).norm(), 0.3);
  // No random part: the seed does not matter.
  EXPECT_EQ(simulateOdometry(truth, *model, 4).back().pose.position, odom.back().pose.position);
}

TEST(SimOdometryDrift, WheelSlipStretchesDistanceAndDriftsHeadingPerMetre) {
  const auto truth = truthAlongLoop(25.0);
  const auto model = odometryErrorPreset("wheel-slip");
  ASSERT_TRUE(model.ok());
  double path = 0.0;
  for (std::size_t i = 1; i < truth.size(); ++i) path += (truth[i].pose.position - truth[i - 1].pose.position).norm();
  // Averaged over seeds so the random walks (0.02 m and 0.005 rad per sqrt(m)) shrink below the tolerances.
  constexpr int kSeeds = 8;
  const std::size_t three_m = 300;  // 3 s at 1 m/s along the first, straight side
  const double true_3m = (truth[three_m].pose.position - truth.front().pose.position).norm();
  double stretched = 0.0, heading = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const auto odom = simulateOdometry(truth, *model, static_cast<std::uint64_t>(seed));
    stretched += (odom[three_m].pose.position - odom.front().pose.position).norm() / kSeeds;
    heading += headingError(odom.back(), truth.back()) / kSeeds;
  }
  EXPECT_NEAR(stretched, 1.03 * true_3m, 0.05);  // 3 % scale error; no error would be 0.09 m short
  EXPECT_NEAR(heading, 0.01 * path, 0.04);       // 0.01 rad per metre: about 0.25 rad after 25 m
  // Deterministic for a seed, different for another.
  EXPECT_EQ(simulateOdometry(truth, *model, 5).back().pose.position,
            simulateOdometry(truth, *model, 5).back().pose.position);
  EXPECT_NE(simulateOdometry(truth, *model, 5).back().pose.position,
            simulateOdometry(truth, *model, 6).back().pose.position);
}

TEST(SimOdometryDrift, SlipAndBiasAddsBothHeadingErrors) {
  const auto truth = truthAlongLoop(25.0);
  const auto slip = odometryErrorPreset("wheel-slip");
  const auto both = odometryErrorPreset("slip-and-bias");
  ASSERT_TRUE(slip.ok() && both.ok());
  // Same seed, same random draws: the difference is the gyro bias alone.
  const auto a = simulateOdometry(truth, *slip, 9);
  const auto b = simulateOdometry(truth, *both, 9);
  const double t = static_cast<double>(truth.back().utime - truth.front().utime) * 1e-6;
  EXPECT_NEAR(std::remainder(yawOf(b.back().pose) - yawOf(a.back().pose), 2.0 * M_PI), 0.0035 * t, 1e-9);
}

TEST(SimOdometry, UnknownPresetListsTheKnownOnes) {
  const auto model = odometryErrorPreset("gyro");
  ASSERT_FALSE(model.ok());
  EXPECT_NE(model.error().message.find("wheel"), std::string::npos);
}

TEST(SimOdometry, CsvHasTheInterfaceHeaderAndRoundTrips) {
  const auto truth = truthAlongLoop(1.0);
  const std::string path = tempPath("poses.csv");
  ASSERT_TRUE(writePoseCsv(path, truth).ok());
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "utime,x,y,z,qw,qx,qy,qz");
  const auto back = readPoseCsv(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  ASSERT_EQ(back->size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ((*back)[i].utime, truth[i].utime);
    EXPECT_NEAR(((*back)[i].pose.position - truth[i].pose.position).norm(), 0.0, 2e-6);
    EXPECT_NEAR((*back)[i].pose.orientation.angularDistance(truth[i].pose.orientation), 0.0, 1e-6);
  }
  std::filesystem::remove(path);
}

TEST(SimOdometry, LcmLogHoldsOdometryOnPoseMatchingTheCsv) {
  const auto truth = truthAlongLoop(1.0);
  const std::string path = tempPath("poses.lcmlog");
  ASSERT_TRUE(writeOdometryLcmLog(path, truth).ok());
  lcm::LogFile log(path, "r");
  ASSERT_TRUE(log.good());
  std::size_t n = 0;
  for (const lcm::LogEvent* ev = log.readNextEvent(); ev != nullptr; ev = log.readNextEvent(), ++n) {
    ASSERT_LT(n, truth.size());
    EXPECT_EQ(ev->channel, "POSE");
    EXPECT_EQ(ev->timestamp, truth[n].utime);
    ogf::odometry_t msg;
    ASSERT_EQ(msg.decode(ev->data, 0, ev->datalen), ev->datalen);
    EXPECT_EQ(msg.utime, truth[n].utime);
    EXPECT_EQ(msg.frame_id, "odom");
    EXPECT_EQ(msg.child_frame_id, "base_link");
    EXPECT_EQ(msg.num_covariance, 0);
    EXPECT_EQ(msg.position[0], truth[n].pose.position.x());
    EXPECT_EQ(msg.position[1], truth[n].pose.position.y());
    EXPECT_EQ(msg.orientation[0], truth[n].pose.orientation.w());
    EXPECT_EQ(msg.orientation[3], truth[n].pose.orientation.z());
  }
  EXPECT_EQ(n, truth.size());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ogf::sim
