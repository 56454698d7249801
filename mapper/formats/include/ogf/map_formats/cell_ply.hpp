// --export-ply: the occupied cells (class +1) as a binary little-endian PLY point cloud that CloudCompare,
// Open3D and MeshLab open: one vertex per cell centre (float x, y, z in metres) with two scalar fields,
// float p (predictive occupancy probability) and float variance.
#pragma once

#include <ogf/common/result.hpp>

#include <filesystem>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_formats {

Status writeOccupiedPly(const MapCells& cells, const std::filesystem::path& path);

}  // namespace ogf::map_formats
