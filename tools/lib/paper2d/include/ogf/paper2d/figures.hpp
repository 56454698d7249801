// The paper's Sec. VI-A figures as PNG files: ground truth and samples (Fig. 2), EP map, OGF map and their
// difference (Fig. 3b-d), d against the number of samples (Fig. 3a) and accuracy against the number of
// samples (Fig. 4a).
#pragma once

#include <filesystem>
#include <span>
#include <string>

#include "ogf/paper2d/experiment.hpp"
#include "ogf/paper2d/ground_truth.hpp"

namespace ogf::paper2d {

// `runs` are the table's rows; `last` is the run whose maps are drawn. False with `error` on a write error.
bool writeFigures(const std::filesystem::path& dir, const GroundTruth& truth, std::span<const Sample> samples,
                  std::span<const ExperimentRun> runs, const ExperimentRun& last, std::string& error);

}  // namespace ogf::paper2d
