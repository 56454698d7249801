// Odometry outputs: exact by default, drifting with an error preset, and the CSV and the LCM log agree.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/odometry_t.hpp>

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
