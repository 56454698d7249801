// The final map of a 2-D SLAM run as a picture: each cell's hit frequency as grey (white free, black
// occupied, mid-grey never observed), the corrected trajectory in red on top.
#pragma once

#include <ogf/slam/pose2.hpp>
#include <ogf/slam/tiled_grid.hpp>
#include <ogf/tools/image.hpp>
#include <vector>

namespace ogf::slam2d {

// One pixel per cell over the observed part of the grid (plus a small margin), north up.
tools::Image renderMap(const slam::TiledGrid& grid, const std::vector<slam::Pose2>& trajectory);

}  // namespace ogf::slam2d
