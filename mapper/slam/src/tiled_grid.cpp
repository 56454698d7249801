// The copy-on-write tiled grid: growth of the tile table and the clone-on-first-write rule.
#include "ogf/slam/tiled_grid.hpp"

#include <algorithm>

namespace ogf::slam {

const GridCell TiledGrid::kEmptyCell{};

namespace {
// Tiles added beyond the one that forced a growth, so a robot driving out of the map does not regrow the
// table at every step.
constexpr int kGrowthMarginTiles = 4;
}  // namespace

TiledGrid::TiledGrid(double resolution_m)
    : resolution_(resolution_m), inverse_resolution_(1.0 / resolution_m) {}

Eigen::Vector2d TiledGrid::meanEndpoint(CellIndex c) const {
  const GridCell& g = cell(c);
  const Eigen::Vector2d corner = cornerOf(c);
  if (g.hits == 0) return corner + Eigen::Vector2d::Constant(0.5 * resolution_);
  const double n = g.hits;
  return corner + Eigen::Vector2d(static_cast<double>(g.end_sum_x) / n, static_cast<double>(g.end_sum_y) / n);
}

void TiledGrid::growToInclude(int tx, int ty) {
  int x0 = tile_x0_, y0 = tile_y0_, x1 = tile_x0_ + tiles_w_, y1 = tile_y0_ + tiles_h_;
  if (tiles_w_ == 0) {
    x0 = tx - kGrowthMarginTiles;
    y0 = ty - kGrowthMarginTiles;
    x1 = tx + kGrowthMarginTiles + 1;
    y1 = ty + kGrowthMarginTiles + 1;
  } else {
    if (tx < x0) x0 = tx - kGrowthMarginTiles;
    if (ty < y0) y0 = ty - kGrowthMarginTiles;
    if (tx >= x1) x1 = tx + kGrowthMarginTiles + 1;
    if (ty >= y1) y1 = ty + kGrowthMarginTiles + 1;
  }
  const int w = x1 - x0, h = y1 - y0;
  std::vector<std::shared_ptr<Tile>> grown(static_cast<std::size_t>(w * h));
  for (int y = 0; y < tiles_h_; ++y) {
    for (int x = 0; x < tiles_w_; ++x) {
      grown[static_cast<std::size_t>((y + tile_y0_ - y0) * w + (x + tile_x0_ - x0))] =
          std::move(tiles_[static_cast<std::size_t>(y * tiles_w_ + x)]);
    }
  }
  tiles_ = std::move(grown);
  tile_x0_ = x0;
  tile_y0_ = y0;
  tiles_w_ = w;
  tiles_h_ = h;
}

GridCell& TiledGrid::mutableCell(CellIndex c) {
  int tx = (c.x >> kTileBits) - tile_x0_, ty = (c.y >> kTileBits) - tile_y0_;
  if (tx < 0 || ty < 0 || tx >= tiles_w_ || ty >= tiles_h_) {
    growToInclude(c.x >> kTileBits, c.y >> kTileBits);
    tx = (c.x >> kTileBits) - tile_x0_;
    ty = (c.y >> kTileBits) - tile_y0_;
  }
  std::shared_ptr<Tile>& t = tiles_[static_cast<std::size_t>(ty * tiles_w_ + tx)];
  if (!t) {
    t = std::make_shared<Tile>();
  } else if (t.use_count() > 1) {
    t = std::make_shared<Tile>(*t);  // copy-on-write: this grid's own copy from now on
  }
  return t->cells[static_cast<std::size_t>(((c.y & (kTileSize - 1)) << kTileBits) | (c.x & (kTileSize - 1)))];
}

void TiledGrid::recordHit(CellIndex c, double endpoint_x, double endpoint_y) {
  GridCell& g = mutableCell(c);
  const Eigen::Vector2d corner = cornerOf(c);
  g.end_sum_x += static_cast<float>(endpoint_x - corner.x());
  g.end_sum_y += static_cast<float>(endpoint_y - corner.y());
  ++g.hits;
  ++g.visits;
}

std::size_t TiledGrid::allocatedTiles() const {
  return static_cast<std::size_t>(
      std::count_if(tiles_.begin(), tiles_.end(), [](const auto& t) { return t != nullptr; }));
}

std::size_t TiledGrid::sharedTilesWith(const TiledGrid& other) const {
  std::size_t n = 0;
  for (int y = 0; y < tiles_h_; ++y) {
    for (int x = 0; x < tiles_w_; ++x) {
      const Tile* t = tiles_[static_cast<std::size_t>(y * tiles_w_ + x)].get();
      if (t == nullptr) continue;
      const int ox = x + tile_x0_ - other.tile_x0_, oy = y + tile_y0_ - other.tile_y0_;
      if (ox < 0 || oy < 0 || ox >= other.tiles_w_ || oy >= other.tiles_h_) continue;
      n += other.tiles_[static_cast<std::size_t>(oy * other.tiles_w_ + ox)].get() == t ? 1U : 0U;
    }
  }
  return n;
}

}  // namespace ogf::slam
