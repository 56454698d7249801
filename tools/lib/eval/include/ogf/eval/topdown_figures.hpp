// ogf-eval --png DIR: top-down views of the ground truth and of each map's classification over a height
// band, x to the right and y up, drawn as figures a person reads without instructions
// (tools::composeMapFigure: at least 800 pixels on the long side, axes in metres, a scale bar, a legend):
//   truth.png                 occupied, free or unobservable (any cell of the column in the band: occupied
//                             wins, then free)
//   <name>_classes.png        occupied, free or unknown (occupied wins, then free)
//   <name>_errors.png         per column, the share of known truth cells in the band the map gets wrong
//                             (unknown counts as wrong, eq. 13), white none to red all; grey no known cell
// The default band shows the walls, not the floor or the ceiling: the truth's walls' band, chosen by the rule
// of the maps' pictures (tools::WallBandFinder, ogf/tools/wall_band.hpp) from its occupied and free cells.
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include <ogf/tools/wall_band.hpp>

#include "ogf/eval/map_scores.hpp"

namespace ogf::sim {
struct GroundTruth;
}

namespace ogf::eval {

struct HeightBand {
  double z_min = 0.0;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 2.0;
};

// The walls' band of the truth (see above) with why it was chosen; nullopt when nothing is occupied.
std::optional<tools::WallBand> wallBand(const sim::GroundTruth& truth);

Status writeTruthPng(const sim::GroundTruth& truth, const HeightBand& band, int scale, const std::filesystem::path& path);
// `estimates` are aligned with truth.cells. Writes DIR/<name>_classes.png and DIR/<name>_errors.png. Each
// cell is at least `scale` pixels wide.
Status writeMapPngs(const sim::GroundTruth& truth, std::span<const CellEstimate> estimates, const HeightBand& band,
                    int scale, const std::filesystem::path& dir, const std::string& name);

}  // namespace ogf::eval
