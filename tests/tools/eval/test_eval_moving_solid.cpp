// A person walks through the simulated lab (ogf-sim --movers person) while the robot maps it; ogf-eval counts
// the cells the person swept that each map still classes occupied at the end. Under the exact filter
// (occupied_priority scan) and the default (map, released after free_release_scans free scans) the trail
// clears as OctoMap's does; under map with no release (0: the paper's rule as stated) it stays.
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

struct LeftBehind {
  long ogf = -1;
  long octomap = -1;
};

// The "... left occupied" row of ogf-eval's table: OGF and OctoMap columns.
std::optional<LeftBehind> leftOccupied(const std::string& table) {
  std::istringstream in(table);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("... left occupied", 0) != 0) continue;
    std::istringstream row(line.substr(std::string("... left occupied").size()));
    LeftBehind l;
    row >> l.ogf >> l.octomap;
    if (row.fail()) return std::nullopt;
    return l;
  }
  return std::nullopt;
}

LeftBehind evaluate(const ScratchDir& dir, const std::string& name, const std::string& yaml) {
  const auto config = dir / (name + ".yaml");
  std::ofstream(config) << yaml;
  const auto run = runProgram({OGF_EVAL_BINARY, "--truth", (dir / "sim").string(), "--config", config.string()},
                              dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const auto left = leftOccupied(run.stdout_text);
  EXPECT_TRUE(left.has_value()) << run.stdout_text;
  return left.value_or(LeftBehind{});
}

TEST(EvalMovingSolid, ThePersonsTrailClearsUnderTheDefaultPolicyAndStaysWithoutRelease) {
  ScratchDir dir;
  const auto sim = runProgram({OGF_SIM_BINARY, "--world", "lab", "--movers", "person", "--duration", "16", "--out",
                               (dir / "sim").string()},
                              dir.path());
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const LeftBehind scan = evaluate(dir, "scan", "filter:\n  occupied_priority: scan\n");
  const LeftBehind byDefault = evaluate(dir, "default", "map:\n  resolution: 0.2\n");
  const LeftBehind never = evaluate(dir, "never", "filter:\n  occupied_priority: map\n  free_release_scans: 0\n");
  SCOPED_TRACE(testing::Message() << "swept cells left occupied: scan " << scan.ogf << ", default "
                                  << byDefault.ogf << ", never released " << never.ogf << ", OctoMap "
                                  << scan.octomap);
  ASSERT_GE(scan.octomap, 0);
  // The exact filter forgets the person at least as well as OctoMap, the default nearly so, and without
  // release several times as many cells stay.
  EXPECT_LE(scan.ogf, scan.octomap + scan.octomap / 10 + 10);
  EXPECT_LE(byDefault.ogf, scan.octomap + scan.octomap / 5 + 20);
  EXPECT_GT(never.ogf, 2 * byDefault.ogf + 100);
}

}  // namespace
