// ogf-slam2d's steps as library functions: the corrector's configuration from the flags (the scan-match
// preset for the flags not given), the result log and the trajectory the relations metric scores.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "ogf/slam2d/run_outputs.hpp"
#include "ogf/slam2d/slam2d_config.hpp"
#include "ogf/slam2d/slam_log.hpp"

namespace ogf::slam2d {
namespace {

TEST(Slam2dConfig, ScanMatchModeTakesThePresetForEveryFlagNotGiven) {
  slam::PoseCorrectorConfig flags;
  flags.slam.linear_update_m = 0.7;
  flags.slam.angular_update_rad = 0.3;
  PresetFlagsGiven given;
  given.linear_update = true;
  const auto config = slam2dConfig(flags, "scan-match", given, true);
  ASSERT_TRUE(config.ok()) << config.error().message;
  const slam::GridFastSlamConfig preset = slam::GridFastSlamConfig::scanMatching();
  EXPECT_EQ(config->mode, slam::CorrectionMode::kScanMatch);
  EXPECT_DOUBLE_EQ(config->slam.linear_update_m, 0.7);  // given: the flag wins
  EXPECT_DOUBLE_EQ(config->slam.angular_update_rad, preset.angular_update_rad);
  EXPECT_DOUBLE_EQ(config->slam.matcher.unmatched_distance_m, preset.matcher.unmatched_distance_m);
  // rbpf keeps the flags' values.
  const auto rbpf = slam2dConfig(flags, "rbpf", {}, false);
  ASSERT_TRUE(rbpf.ok()) << rbpf.error().message;
  EXPECT_DOUBLE_EQ(rbpf->slam.angular_update_rad, 0.3);
  EXPECT_FALSE(rbpf->slam.two_step_sampling);
  EXPECT_DOUBLE_EQ(rbpf->slam.matcher.usable_range_m, rbpf->slam.map_update.usable_range_m);
}

TEST(Slam2dConfig, AnUnknownModeAndAnInvalidConfigurationAreRefused) {
  const auto mode = slam2dConfig({}, "sideways", {}, true);
  ASSERT_FALSE(mode.ok());
  EXPECT_EQ(mode.error().message.rfind("--mode: ", 0), 0U) << mode.error().message;
  slam::PoseCorrectorConfig none;
  none.slam.particles = 0;
  const auto invalid = slam2dConfig(none, "rbpf", {}, true);
  ASSERT_FALSE(invalid.ok());
  EXPECT_EQ(invalid.error().message.rfind("configuration: ", 0), 0U) << invalid.error().message;
}

std::string flaser(double x, const char* stamp) {
  std::ostringstream s;
  s << "FLASER 2 1.0 2.0 " << x << " 0 0 " << x << " 0 0 " << stamp << " host 0.0\n";
  return s.str();
}

TEST(RunOutputs, TrajectoryIsSortedByStampWithEqualStampsInLogOrder) {
  std::istringstream in(flaser(1, "3.0") + flaser(2, "1.0") + flaser(3, "3.0") + flaser(4, "2.0"));
  const SlamLog log = readSlamLog(in, "mem");
  ASSERT_EQ(log.lasers.size(), 4U);
  const std::vector<slam::Pose2> corrected{{1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}};
  const auto t = stampedTrajectory(log, corrected);
  ASSERT_EQ(t.size(), 4U);
  EXPECT_DOUBLE_EQ(t[0].pose.x, 2.0);
  EXPECT_DOUBLE_EQ(t[1].pose.x, 4.0);
  EXPECT_DOUBLE_EQ(t[2].pose.x, 1.0);
  EXPECT_DOUBLE_EQ(t[3].pose.x, 3.0);
}

TEST(RunOutputs, ResultLogHoldsOneRecordPerLaserAndAnUnwritablePathIsAnError) {
  std::istringstream in(flaser(1, "1.0") + flaser(2, "2.0"));
  const SlamLog log = readSlamLog(in, "mem");
  const std::vector<slam::Pose2> corrected{{5, 6, 0}, {7, 8, 0}};
  const auto path =
      std::filesystem::temp_directory_path() / ("ogf-slam2d-result-" + std::to_string(::getpid()));
  ASSERT_TRUE(writeResultLog(path.string(), log, corrected).ok());
  std::ifstream back(path);
  std::istringstream copy(std::string(std::istreambuf_iterator<char>(back), {}));
  const SlamLog written = readSlamLog(copy, "result");
  std::filesystem::remove(path);
  ASSERT_EQ(written.lasers.size(), 2U);
  EXPECT_DOUBLE_EQ(written.lasers[1].laser_pose.x, 7.0);
  EXPECT_DOUBLE_EQ(written.lasers[1].robot_pose.y, 8.0);
  const auto st = writeResultLog("/nonexistent/dir/result.clf", log, corrected);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "cannot write /nonexistent/dir/result.clf");
}

}  // namespace
}  // namespace ogf::slam2d
