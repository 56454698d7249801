// The 2-D navigation grid (mapper/navigation) of a map, and the pair of files the navigation stacks' map
// servers load (ROS map_server and nav2_map_server, "Map format" of their documentation): DIR/map.pgm, a
// binary greyscale PGM (P5, maxval 255) whose first row is the grid's northernmost (the loaders flip it, so
// the map's lower-left pixel is the grid's south-west column), and DIR/map.yaml:
//   image: map.pgm            the picture, relative to the YAML file
//   mode: trinary | scale
//   resolution: 0.2           metres per pixel
//   origin: [x, y, 0.0]       the pose of the lower-left pixel's corner, metres, yaw 0
//   negate: 0                 darker is more occupied: a loader reads p = (255 - pixel) / 255
//   occupied_thresh, free_thresh
// trinary (what map_saver writes): occupied 0, free 254, unknown 205; with occupied_thresh 0.65 and
//   free_thresh 0.196 a loader reads back exactly the three classes (205 reads p = 0.19608, not below 0.196).
// scale: the pixel holds the column's cost, 255 - round(2.55 · cost), with free_thresh 0 and occupied_thresh 1,
//   so nav2_map_server, which reads rint(100 (p − free) / (occupied − free)) between the thresholds
//   (map_io.cpp, loadMapFromFile), reads the cost back exactly; ROS 1's map_server reads 1 + 98 times that
//   ratio, within two of it. A greyscale PGM has no alpha channel, the only way a scale-mode loader learns
//   "unknown": unknown columns are written 205 and read back as a cost of about 20. Planners that need
//   unknown space use trinary.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/navigation/nav_band.hpp>
#include <ogf/navigation/nav_grid.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "ogf/map_formats/map_cells.hpp"

namespace ogf::map_formats {

enum class NavImageMode { kTrinary, kScale };

// "trinary" or "scale"; an error naming the choices otherwise.
Result<NavImageMode> parseNavImageMode(std::string_view text);
std::string_view toString(NavImageMode mode);

// The map's grid over `band` (NavBand::validate's error when the band holds no layer at the map's resolution).
Result<navigation::NavGrid> projectCells(const MapCells& cells, const navigation::NavBand& band);

// The pixel of a column in `mode`.
std::uint8_t navPixel(const navigation::NavColumn& column, NavImageMode mode);

struct NavMapFiles {
  std::filesystem::path pgm, yaml;
  std::size_t free = 0, occupied = 0, unknown = 0;  // columns of the picture
};

// Writes DIR/map.pgm and DIR/map.yaml, creating DIR. Errors name the file: a folder that cannot be made, a
// write that fails, or a grid with no known column (nothing to draw).
Result<NavMapFiles> writeNavMap(const navigation::NavGrid& grid, const std::filesystem::path& dir, NavImageMode mode);

}  // namespace ogf::map_formats
