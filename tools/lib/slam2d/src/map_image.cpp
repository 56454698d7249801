// Rendering a TiledGrid and a trajectory into an Image.
#include "ogf/slam2d/map_image.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

namespace ogf::slam2d {

namespace {
constexpr int kMarginCells = 10;
constexpr tools::Rgb kUnknown{160, 160, 160};
constexpr tools::Rgb kTrajectory{220, 30, 30};
}  // namespace

tools::Image renderMap(const slam::TiledGrid& grid, const std::vector<slam::Pose2>& trajectory) {
  // The observed extent: the allocated tile area can be much larger than the cells that were seen.
  const slam::CellIndex lo = grid.minCell(), hi = grid.maxCell();
  int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
  for (int y = lo.y; y < hi.y; ++y) {
    for (int x = lo.x; x < hi.x; ++x) {
      if (grid.cell({x, y}).visits == 0) continue;
      x0 = std::min(x0, x);
      y0 = std::min(y0, y);
      x1 = std::max(x1, x);
      y1 = std::max(y1, y);
    }
  }
  if (x0 > x1) return tools::Image::rgb(1, 1, kUnknown);
  x0 -= kMarginCells;
  y0 -= kMarginCells;
  x1 += kMarginCells;
  y1 += kMarginCells;
  const int w = x1 - x0 + 1, h = y1 - y0 + 1;
  tools::Image img = tools::Image::rgb(w, h, kUnknown);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double p = grid.occupancy({x, y});
      if (p < 0.0) continue;
      // Hit frequencies above ~0.25 are walls; stretch so they print black.
      const double darkness = std::min(1.0, p * 4.0);
      const auto v = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - darkness)));
      img.set(x - x0, y1 - y, {v, v, v});
    }
  }
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    const slam::CellIndex a = grid.cellOf(trajectory[i - 1].x, trajectory[i - 1].y);
    const slam::CellIndex b = grid.cellOf(trajectory[i].x, trajectory[i].y);
    img.drawLine(a.x - x0, y1 - a.y, b.x - x0, y1 - b.y, kTrajectory);
  }
  return img;
}

}  // namespace ogf::slam2d
