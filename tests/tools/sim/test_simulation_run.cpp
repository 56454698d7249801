// A whole run: every output file appears, the same seed gives identical bytes, another seed does not.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "ogf/sim/pose_files.hpp"
#include "ogf/sim/simulation.hpp"
#include "sim_test_paths.hpp"
#include "support/file_text.hpp"

namespace ogf::sim {
namespace {

using ogf::testing::fileText;

class SimulationRun : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = test::scratchPath("run_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(base_);
    auto scene = presetScene("lab");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    scene_ = *scene;
    auto spec = resolveTrajectory(scene_, "loop");
    ASSERT_TRUE(spec.ok());
    spec_ = *spec;
    config_.duration_s = 0.3;
    config_.sensor.dropout = 0.01;
  }
  void TearDown() override { std::filesystem::remove_all(base_); }

  Result<SimulationReport> run(const std::string& name) {
    return runSimulation(scene_, spec_, config_, (base_ / name).string());
  }

  std::filesystem::path base_;
  Scene scene_;
  TrajectorySpec spec_;
  SimulationConfig config_;
};

const char* const kOutputs[] = {"capture.pcap", "odometry.csv", "odometry.lcmlog", "trajectory_true.csv",
                                "truth.grid", "sim.yaml"};

TEST_F(SimulationRun, SameSeedWritesIdenticalFiles) {
  config_.odometry_error = *odometryErrorPreset("wheel");
  ASSERT_TRUE(run("a").ok());
  ASSERT_TRUE(run("b").ok());
  for (const char* f : kOutputs) {
    ASSERT_TRUE(std::filesystem::exists(base_ / "a" / f)) << f;
    EXPECT_EQ(fileText(base_ / "a" / f), fileText(base_ / "b" / f)) << f;
  }
  config_.sensor.seed = 2;
  ASSERT_TRUE(run("c").ok());
  EXPECT_NE(fileText(base_ / "a" / "capture.pcap"), fileText(base_ / "c" / "capture.pcap"));
  EXPECT_NE(fileText(base_ / "a" / "odometry.csv"), fileText(base_ / "c" / "odometry.csv"));
  EXPECT_EQ(fileText(base_ / "a" / "trajectory_true.csv"), fileText(base_ / "c" / "trajectory_true.csv"));
}

TEST_F(SimulationRun, PosesCoverTheCaptureOnItsClock) {
  const auto report = run("clock");
  ASSERT_TRUE(report.ok()) << report.error().message;
  const auto truth = readPoseCsv((base_ / "clock" / "trajectory_true.csv").string());
  const auto odom = readPoseCsv((base_ / "clock" / "odometry.csv").string());
  ASSERT_TRUE(truth.ok() && odom.ok());
  ASSERT_EQ(truth->size(), odom->size());
  EXPECT_EQ(truth->front().utime, config_.start_utime);
  EXPECT_EQ(report->capture.first_utime, config_.start_utime);
  // Poses reach past the last firing of the last packet (1.327 ms after its stamp).
  EXPECT_GE(truth->back().utime, report->capture.last_utime + 1328);
  for (std::size_t i = 1; i < truth->size(); ++i) EXPECT_EQ((*truth)[i].utime - (*truth)[i - 1].utime, 10000);
  // Exact odometry by default.
  for (std::size_t i = 0; i < truth->size(); ++i) EXPECT_EQ((*truth)[i].pose.position, (*odom)[i].pose.position);
  const auto grid = readGroundTruth((base_ / "clock" / "truth.grid").string());
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(grid->cells, report->truth.cells);
}

}  // namespace
}  // namespace ogf::sim
