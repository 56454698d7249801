// --png DIR: two top-down views of the map over a height band [z_min, z_max], one pixel per cell column,
// x to the right and y up: occupancy.png, the largest predictive probability of the cells in the band
// (white 0, black 1; a column with no allocated cell reads as the prior 0.5, mid grey), and entropy.png,
// the mean binary entropy in bits of the cells in the band (black 0, white 1 bit; the prior is 1 bit).
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>

#include "ogf/map_io/map_cells.hpp"

namespace ogf::map_io {

struct TopDownBand {
  double z_min = -1.0e9;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 1.0e9;
};

struct TopDownSize {
  int width = 0;
  int height = 0;
};

// Writes DIR/occupancy.png and DIR/entropy.png (creating DIR). Error when no cell lies in the band or the
// image would exceed 16384 pixels on a side.
Result<TopDownSize> writeTopDownPngs(const MapCells& cells, const TopDownBand& band, const std::filesystem::path& dir);

}  // namespace ogf::map_io
