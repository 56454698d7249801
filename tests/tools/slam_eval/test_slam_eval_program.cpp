// ogf-slam-eval run as a real process: the three lines it prints on a small result log whose errors were
// computed by hand, a non-zero exit with a clear message on unreadable files, malformed relations and
// relations no result pose matches, exit 2 on a missing flag, and the Intel log's raw-odometry score.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "support/shared_data.hpp"
#include "tools/map/run_program.hpp"
#include "tools/map/scratch_dir.hpp"

namespace {

using ogf::testing::runProgram;
using ogf::testing::ScratchDir;

const std::string kSlamEval = OGF_SLAM_EVAL_BINARY;

void writeFile(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

// ogf-slam-eval --result <dir/result> --relations <dir/relations>.
ogf::testing::ProgramRun runEval(const ScratchDir& dir, const std::string& result,
                                 const std::string& relations) {
  return runProgram(
      {kSlamEval, "--result", (dir / result).string(), "--relations", (dir / relations).string()},
      dir.path());
}

// Three FLASER records whose robot (second) triples are (0, 0, 0), (1, 0, 0) and (1, 1, pi/2); the last
// one's first (laser) triple is elsewhere, and a comment and an ODOM line: the metric must ignore all three.
const std::string kResultLog =
    "# result log\n"
    "ODOM 5 5 0 0 0 0 10.000001 nohost 0\n"
    "FLASER 2 1.0 2.0 0 0 0 0 0 0 10.000001 nohost 0.1\n"
    "FLASER 2 1.0 2.0 1 0 0 1 0 0 11.000002 nohost 1.1\n"
    "FLASER 2 1.0 2.0 9 9 0 1 1 1.570796 12.000003 nohost 2.1\n";

// Errors: exact; 0.5 m off in y; 0.2 rad off in yaw.
// trans {0, 0.5, 0}: mean 0.1667, sample std sqrt(1/12) = 0.2887, max 0.5.
// rot {0, 0, 11.4592 deg}: mean 3.8197, sample std 6.6159.
// Squared: trans {0, 0.25, 0}: 0.0833 ± 0.1443; rot {0, 0, 131.3123}: 43.7708 ± 75.8132.
const std::string kRelations =
    "10.000001 11.000002 1 0 0 0 0 0\n"
    "11.000002 12.000003 0 0.5 0 0 0 1.570796\n"
    "10.000001 12.000003 1 1 0 0 0 1.370796\n";

// Writes result.log and truth.relations with the given texts and scores the one against the other.
ogf::testing::ProgramRun evalTexts(const ScratchDir& dir, const std::string& result,
                                   const std::string& relations) {
  writeFile(dir / "result.log", result);
  writeFile(dir / "truth.relations", relations);
  return runEval(dir, "result.log", "truth.relations");
}

TEST(SlamEvalProgram, PrintsTheHandComputedMetric) {
  ScratchDir dir;
  const auto run = evalTexts(dir, kResultLog, kRelations);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.stdout_text,
            "trans 0.1667 ± 0.2887 m max 0.5000\n"
            "rot 3.8197 ± 6.6159 deg\n"
            "relations 3 matched, 0 unmatched of 3; rot max 11.4592 deg\n"
            "sqr trans 0.0833 ± 0.1443 m^2, sqr rot 43.7708 ± 75.8132 deg^2\n");
}

TEST(SlamEvalProgram, MatchesStampsPrintedWithFewerDecimals) {
  ScratchDir dir;
  const auto run = evalTexts(dir, kResultLog, "10.00000 11.00000 1 0 0 0 0 0\n12.9 13.9 1 0 0 0 0 0\n");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.stdout_text.find("trans 0.0000 ± 0.0000 m max 0.0000\n"), std::string::npos) << run.output;
  EXPECT_NE(run.stdout_text.find("relations 1 matched, 1 unmatched of 2"), std::string::npos) << run.output;
}

TEST(SlamEvalProgram, NoMatchingRelationExitsNonZero) {
  ScratchDir dir;
  const auto run = evalTexts(dir, kResultLog, "976052905.167303 976052911.885496 1 0 0 0 0 0\n");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("no relation matched"), std::string::npos) << run.output;
  EXPECT_EQ(run.stdout_text, "");
}

TEST(SlamEvalProgram, UnreadableOrMalformedFilesExitNonZeroNamingThem) {
  ScratchDir dir;
  writeFile(dir / "result.log", kResultLog);
  writeFile(dir / "bad.relations", "10.000001 11.000002 1 0 0 0 0 0\n10.000001 11.000002 1 0 0\n");
  const auto missing = runEval(dir, "absent.log", "bad.relations");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("absent.log"), std::string::npos) << missing.output;

  const auto malformed = runEval(dir, "result.log", "bad.relations");
  EXPECT_EQ(malformed.exit_code, 1);
  EXPECT_NE(malformed.output.find("bad.relations:2:"), std::string::npos) << malformed.output;

  writeFile(dir / "empty.log", "# nothing\nODOM 0 0 0 0 0 0 1.0 nohost 0\n");
  const auto empty = runEval(dir, "empty.log", "bad.relations");
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.output.find("no FLASER or ROBOTLASER1"), std::string::npos) << empty.output;
}

TEST(SlamEvalProgram, MalformedResultLinesAreReportedAndSkipped) {
  ScratchDir dir;
  const auto run = evalTexts(dir, kResultLog + "FLASER 3 1.0 2.0 0 0 0 0 0 0 13.0 nohost 0\n", kRelations);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("result.log:6: FLASER"), std::string::npos) << run.output;
  EXPECT_NE(run.stdout_text.find("relations 3 matched"), std::string::npos) << run.output;
}

TEST(SlamEvalProgram, MissingFlagIsAUsageError) {
  ScratchDir dir;
  const auto run = runProgram({kSlamEval, "--relations", "x.relations"}, dir.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
}

TEST(SlamEvalProgram, ScoresTheIntelRawOdometry) {
  OGF_REQUIRE_SHARED_FILE(log_path, "data/slam/intel.clf");
  OGF_REQUIRE_SHARED_FILE(relations_path, "data/slam/intel.relations");
  ScratchDir dir;
  const auto run = runProgram(
      {kSlamEval, "--result", log_path.string(), "--relations", relations_path.string()}, dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  // Raw odometry alone scores Intel 7.37 ± 14.35 m (docs/test-data.md §3.1).
  EXPECT_EQ(run.stdout_text.substr(0, run.stdout_text.find('\n')), "trans 7.3702 ± 14.3515 m max 70.0215");
  EXPECT_NE(run.stdout_text.find("relations 2984 matched, 0 unmatched of 2984"), std::string::npos);
}

}  // namespace
