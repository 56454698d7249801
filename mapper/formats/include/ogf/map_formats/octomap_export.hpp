// --export-bt: the map as an OctoMap binary tree (.bt) for octovis and every OctoMap user, written with
// liboctomap itself. The tree has the map's resolution and one leaf per classified cell: occupied cells
// (class +1) get the log-odds of their probability, free cells (class -1) likewise, unknown cells are left
// out (unknown in OctoMap too). OctoMap's key is floor(coordinate / resolution) + 32768 per axis, the same
// cell boundaries as CellKey, so every cell lands in exactly its own leaf; cells beyond OctoMap's ±32768
// cell extent are counted and left out.
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_formats {

struct OctomapExportCounts {
  std::int64_t occupied = 0;
  std::int64_t free = 0;
  std::int64_t out_of_range = 0;
};

Result<OctomapExportCounts> writeOctomapBinary(const MapCells& cells, const std::filesystem::path& path);

}  // namespace ogf::map_formats
