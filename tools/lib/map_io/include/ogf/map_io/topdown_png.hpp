// --png DIR: two top-down views of the map over a height band, x to the right and y up, drawn as figures a
// person reads without instructions (tools::composeMapFigure: at least 800 pixels on the long side, axes in
// metres, a scale bar, a legend or colour bar):
//   occupancy.png  per cell column in the band: occupied when any cell is, else free when any cell is, else
//                  unknown (cells between the thresholds), else not observed (no cell allocated)
//   entropy.png    the mean binary entropy in bits of the column's cells (the prior is 1 bit), colour bar
// The default band shows the walls, not the floor or the ceiling, and is chosen from the map's cells
// (tools::WallBandFinder, ogf/tools/wall_band.hpp): occupied runs at most 0.6 m thick with free cells within
// 0.2 m above or below them are horizontal surfaces (the rays passed over a floor or under a ceiling), other
// occupied cells stand up; layers holding more surface cells than standing ones are floors and ceilings; the
// band is 1.8 m of the storey between them that holds the most standing cells, placed where the most columns
// hold standing cells (the lowest within 5 % of the best). It needs no floor at z = 0
// and no floor seen more than the ceiling: it works in the sensor's frame, with any extrinsic, indoors and
// out. The programs log the band and why (floor and ceiling heights, wall columns).
#pragma once

#include <cstdint>
#include <filesystem>
#include <ogf/common/result.hpp>
#include <ogf/tools/wall_band.hpp>
#include <optional>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_io {

struct TopDownBand {
  double z_min = -1.0e9;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 1.0e9;
};

// The cell columns a picture covers, x0..x1 by y0..y1 inclusive (cell keys): a picture drawn beside others
// of the same area (ogf-eval's, over the truth's grid) lines up with them pixel for pixel.
struct TopDownArea {
  std::int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct TopDownSize {
  int width = 0;  // cell columns
  int height = 0;
};

// The walls' band of the map (see above) with why it was chosen; nullopt when no cell is occupied.
std::optional<tools::WallBand> wallBand(const map_formats::MapCells& cells);

// Writes DIR/occupancy.png and DIR/entropy.png (creating DIR), over `area` when given (cells outside it are
// left out), else over the columns the band's cells cover. Error when no cell lies in the band or the
// picture would exceed 16384 cells on a side.
Result<TopDownSize> writeTopDownPngs(const map_formats::MapCells& cells, const TopDownBand& band,
                                     const std::filesystem::path& dir,
                                     const std::optional<TopDownArea>& area = std::nullopt);

}  // namespace ogf::map_io
