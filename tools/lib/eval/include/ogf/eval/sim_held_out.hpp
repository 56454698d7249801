// The held-out test on a simulator run (held_out.hpp): an OGF (through the daemon's mapping pipeline) and
// an OctoMap are built from the rays the split keeps of the run's recomputed rays (sim_measurements.hpp)
// and scored on the rays it holds out.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/map_io/scan_record.hpp>
#include <ogf/pipeline/mapper_config.hpp>

#include <filesystem>
#include <vector>

#include "ogf/eval/held_out.hpp"
#include "ogf/eval/sim_measurements.hpp"

namespace ogf::eval {

struct SimHeldOut {
  std::vector<HeldOutScores> scores;  // the OGF's, then the OctoMap's when it was asked for
  SimMeasurementCounts counts;        // of the replay of the run's rays
};

// The run in `sim_dir` replayed through `config` on the clock `time_base` names; `octomap` adds its column.
Result<SimHeldOut> heldOutOnSimRun(const std::filesystem::path& sim_dir, const pipeline::MapperConfig& config,
                                   map_io::TimeBase time_base, const HeldOutSplit& split, bool octomap);

}  // namespace ogf::eval
