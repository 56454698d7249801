// ogf-eval --png DIR: top-down views of the ground truth and of each map's classification over a height
// band, one square of `scale` pixels per truth cell column, x to the right and y up:
//   truth.png                 black occupied, white free, dark grey unobservable (any cell of the column in
//                             the band: occupied wins, then free)
//   <name>_classes.png        black occupied, white free, mid grey unknown (occupied wins, then free)
//   <name>_errors.png         per column, the share of known truth cells in the band the map gets wrong
//                             (unknown counts as wrong, eq. 13): white none, red all; dark grey no known cell
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>
#include <span>
#include <string>

#include "ogf/eval/map_scores.hpp"

namespace ogf::sim {
struct GroundTruth;
}

namespace ogf::eval {

struct HeightBand {
  double z_min = 0.1;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 2.0;
};

Status writeTruthPng(const sim::GroundTruth& truth, const HeightBand& band, int scale, const std::filesystem::path& path);
// `estimates` are aligned with truth.cells. Writes DIR/<name>_classes.png and DIR/<name>_errors.png.
Status writeMapPngs(const sim::GroundTruth& truth, std::span<const CellEstimate> estimates, const HeightBand& band,
                    int scale, const std::filesystem::path& dir, const std::string& name);

}  // namespace ogf::eval
