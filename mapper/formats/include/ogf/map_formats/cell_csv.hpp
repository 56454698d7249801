// --export-csv: every allocated cell as one CSV row, header `x,y,z,p,class,variance`: the cell centre in
// metres (map frame), the predictive occupancy probability, the class of eq. (3) (-1 free, 0 unknown,
// 1 occupied) and the latent variance.
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_formats {

inline constexpr const char* kCellCsvHeader = "x,y,z,p,class,variance";

Status writeCellCsv(const MapCells& cells, const std::filesystem::path& path);

}  // namespace ogf::map_formats
