// ogf-eval's absolute trajectory error as a process: on a run folder holding only trajectory_true.csv it
// prints one row per given trajectory with the RMSE, mean and max computed by hand, without a trajectory
// scores the run's map (built here without --map) and names a missing truth, and exits 1 naming a file whose
// stamps match nothing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ogf/sim/pose_files.hpp"
#include "tools/map/run_program.hpp"
#include "tools/map/scratch_dir.hpp"

namespace {

using ogf::sim::StampedPose;
using ogf::testing::runProgram;
using ogf::testing::ScratchDir;

const std::string kEval = OGF_EVAL_BINARY;
constexpr std::int64_t kStart = 1704110400000000LL;

std::vector<StampedPose> line(double y_offset, double y_growth) {
  std::vector<StampedPose> poses;
  for (int i = 0; i <= 4; ++i) {
    StampedPose p;
    p.utime = kStart + i * 10'000;
    p.pose.position = Eigen::Vector3d(0.01 * i, y_offset + y_growth * i, 0.0);
    poses.push_back(p);
  }
  return poses;
}

TEST(EvalTrajectoryProgram, PrintsTheAteOfRawAndCorrectedPoses) {
  ScratchDir dir;
  ASSERT_TRUE(ogf::sim::writePoseCsv((dir / "trajectory_true.csv").string(), line(0.0, 0.0)).ok());
  // Raw: y errors 0, 0.1, 0.2, 0.3, 0.4 m: mean 0.2, RMSE sqrt(0.3/5) = 0.2449, max 0.4.
  ASSERT_TRUE(ogf::sim::writePoseCsv((dir / "odometry.csv").string(), line(0.0, 0.1)).ok());
  // Corrected: 0.01 m everywhere.
  ASSERT_TRUE(ogf::sim::writePoseCsv((dir / "corrected.csv").string(), line(0.01, 0.0)).ok());
  const auto run =
      runProgram({kEval, "--truth", dir.path().string(), "--odometry", (dir / "odometry.csv").string(),
                  "--corrected", (dir / "corrected.csv").string()},
                 dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.stdout_text.find("no alignment"), std::string::npos) << run.stdout_text;
  EXPECT_NE(run.stdout_text.find(
                "odometry (raw)                            5       0.2449       0.2000       0.4000"),
            std::string::npos)
      << run.stdout_text;
  EXPECT_NE(run.stdout_text.find(
                "corrected                                 5       0.0100       0.0100       0.0100"),
            std::string::npos)
      << run.stdout_text;
}

TEST(EvalTrajectoryProgram, WithoutATrajectoryOrAMapTheRunsTruthIsScoredAndItsAbsenceNamed) {
  ScratchDir dir;
  const auto run = runProgram({kEval, "--truth", dir.path().string()}, dir.path());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("truth.grid: cannot open"), std::string::npos) << run.output;
}

TEST(EvalTrajectoryProgram, TrajectoryMatchingNoTrueStampFails) {
  ScratchDir dir;
  ASSERT_TRUE(ogf::sim::writePoseCsv((dir / "trajectory_true.csv").string(), line(0.0, 0.0)).ok());
  auto late = line(0.0, 0.0);
  for (auto& p : late) p.utime += 10'000'000;
  ASSERT_TRUE(ogf::sim::writePoseCsv((dir / "late.csv").string(), late).ok());
  const auto run = runProgram(
      {kEval, "--truth", dir.path().string(), "--corrected", (dir / "late.csv").string()}, dir.path());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("late.csv: no pose matches"), std::string::npos) << run.output;
}

}  // namespace
