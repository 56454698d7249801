// The simulated lab's 2-D navigation grid (ogf-eval --nav) against the run's ground truth: the robot's free
// corridors come out free and the walls, furniture and pillar occupied, column by column over the band.
#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "tools/map/run_program.hpp"
#include "tools/map/scratch_dir.hpp"

namespace {

using ogf::testing::runProgram;
using ogf::testing::ScratchDir;

// The first number after `label` on the line that starts with it, and the one after `word` on that line.
std::optional<double> valueAfter(const std::string& table, const std::string& label, const std::string& word) {
  std::istringstream in(table);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(label, 0) != 0) continue;
    const auto at = line.find(word, label.size());
    if (at == std::string::npos) return std::nullopt;
    return std::stod(line.substr(at + word.size()));
  }
  return std::nullopt;
}

TEST(EvalNavProgram, TheLabsFreeColumnsComeOutFreeAndItsWallsOccupied) {
  ScratchDir dir;
  const auto sim = runProgram({OGF_SIM_BINARY, "--world", "lab", "--duration", "10", "--out", (dir / "sim").string()},
                              dir.path());
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const auto run = runProgram({OGF_EVAL_BINARY, "--truth", (dir / "sim").string(), "--no-octomap", "--nav"}, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto& t = run.stdout_text;
  const auto free_free = valueAfter(t, "nav truth free columns", "free ");
  const auto free_occupied = valueAfter(t, "nav truth free columns", "occupied ");
  const auto occupied_occupied = valueAfter(t, "nav truth occupied columns", "occupied ");
  const auto occupied_free = valueAfter(t, "nav truth occupied columns", "free ");
  const auto accuracy = valueAfter(t, "nav accuracy", " ");
  ASSERT_TRUE(free_free && free_occupied && occupied_occupied && occupied_free && accuracy) << t;
  SCOPED_TRACE(t);
  // Measured on the 10 s lab loop: 0.95 of the free columns free, 0.89 of the occupied ones occupied (the glass
  // partition lets rays through); the occupied share of free columns is the walls' kernel-wide rim.
  EXPECT_GE(*free_free, 0.90);
  EXPECT_LE(*free_occupied, 0.08);
  EXPECT_GE(*occupied_occupied, 0.85);
  EXPECT_LE(*occupied_free, 0.10);
  EXPECT_GE(*accuracy, 0.90);
}

}  // namespace
