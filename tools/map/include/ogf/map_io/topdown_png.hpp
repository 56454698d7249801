// --png DIR: two top-down views of the map over a height band, x to the right and y up, drawn as figures a
// person reads without instructions (tools::composeMapFigure: at least 800 pixels on the long side, axes in
// metres, a scale bar, a legend or colour bar):
//   occupancy.png  per cell column in the band: occupied when any cell is, else free when any cell is, else
//                  unknown (cells between the thresholds), else not observed (no cell allocated)
//   entropy.png    the mean binary entropy in bits of the column's cells (the prior is 1 bit), colour bar
// The default band shows walls, not the floor: from 0.2 m above the floor to 2 m above it, the floor being
// the lowest layer of cells that holds at least half as many occupied cells as the fullest layer (with the
// layers right above it that do too: range noise spreads a floor over two).
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>
#include <optional>

#include "ogf/map_io/map_cells.hpp"

namespace ogf::map_io {

struct TopDownBand {
  double z_min = -1.0e9;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 1.0e9;
};

struct TopDownSize {
  int width = 0;   // cell columns
  int height = 0;
};

// The walls' band of the map (see above); nullopt when no cell is occupied.
std::optional<TopDownBand> wallBand(const MapCells& cells);

// Writes DIR/occupancy.png and DIR/entropy.png (creating DIR). Error when no cell lies in the band or the
// map would exceed 16384 cells on a side.
Result<TopDownSize> writeTopDownPngs(const MapCells& cells, const TopDownBand& band, const std::filesystem::path& dir);

}  // namespace ogf::map_io
