// --export-pcd: the occupied cells (class +1) as a binary PCD v0.7 point cloud that PCL, CloudCompare and
// Open3D open: one point per cell centre (float x, y, z in metres) with the fields p (predictive occupancy
// probability) and variance, VIEWPOINT at the map origin.
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_formats {

Status writeOccupiedPcd(const MapCells& cells, const std::filesystem::path& path);

}  // namespace ogf::map_formats
