// The 2-D map each RBPF particle carries: GMapping's point-accumulator grid (Grisetti et al. 2007,
// Sec. IV; gmapping's HierarchicalArray2D of PointAccumulator), stored as 32×32-cell tiles held by
// shared_ptr. Copying a grid copies only the tile pointers; a tile is cloned the first time a grid that
// shares it writes to it (copy-on-write), so N particles that descend from one ancestor share every tile
// none of them has changed since, and memory grows with what the particles changed, not with N × map.
// The grid grows on demand in every direction. Not thread-safe: particles must be updated by one thread,
// since the copy-on-write test reads shared_ptr::use_count().
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace ogf::slam {

struct CellIndex {
  int x = 0;
  int y = 0;
  friend bool operator==(const CellIndex&, const CellIndex&) = default;
};

// One cell: how often a beam passed through or ended in it, and where beams ended inside it (sum of the
// endpoint offsets from the cell's lower-left corner, so float sums stay precise far from the origin).
struct GridCell {
  float end_sum_x = 0.0F;
  float end_sum_y = 0.0F;
  std::uint32_t hits = 0;    // beams that ended here
  std::uint32_t visits = 0;  // beams that passed through or ended here

  // The hit frequency, gmapping's PointAccumulator value; -1 for a cell never observed.
  double occupancy() const { return visits == 0 ? -1.0 : static_cast<double>(hits) / visits; }
};

class TiledGrid {
 public:
  static constexpr int kTileBits = 5;
  static constexpr int kTileSize = 1 << kTileBits;  // cells per tile edge
  static constexpr int kCellsPerTile = kTileSize * kTileSize;
  struct Tile {
    std::array<GridCell, kCellsPerTile> cells{};
  };

  explicit TiledGrid(double resolution_m = 0.05);

  double resolution() const { return resolution_; }
  CellIndex cellOf(double x, double y) const {
    return {static_cast<int>(std::floor(x * inverse_resolution_)),
            static_cast<int>(std::floor(y * inverse_resolution_))};
  }
  // The lower-left corner of a cell, metres.
  Eigen::Vector2d cornerOf(CellIndex c) const { return {c.x * resolution_, c.y * resolution_}; }

  // The cell, or an empty (never observed) cell outside the allocated tiles. Never allocates.
  const GridCell& cell(CellIndex c) const {
    const int tx = (c.x >> kTileBits) - tile_x0_, ty = (c.y >> kTileBits) - tile_y0_;
    if (tx < 0 || ty < 0 || tx >= tiles_w_ || ty >= tiles_h_) return kEmptyCell;
    const Tile* t = tiles_[static_cast<std::size_t>(ty * tiles_w_ + tx)].get();
    if (t == nullptr) return kEmptyCell;
    return t
        ->cells[static_cast<std::size_t>(((c.y & (kTileSize - 1)) << kTileBits) | (c.x & (kTileSize - 1)))];
  }
  // Hit frequency of the cell (GridCell::occupancy), -1 when unknown.
  double occupancy(CellIndex c) const { return cell(c).occupancy(); }
  // The mean of the beam endpoints in the cell, metres (the cell centre when it has no hit).
  Eigen::Vector2d meanEndpoint(CellIndex c) const;

  // The cell for writing: grows the grid, allocates the tile, and clones it first if another grid
  // shares it.
  GridCell& mutableCell(CellIndex c);
  // A beam passed through the cell.
  void recordVisit(CellIndex c) { ++mutableCell(c).visits; }
  // A beam ended in the cell at (endpoint_x, endpoint_y), metres in the map frame.
  void recordHit(CellIndex c, double endpoint_x, double endpoint_y);

  // Inspection: tiles allocated, and how many of them are the same object in `other`.
  std::size_t allocatedTiles() const;
  std::size_t sharedTilesWith(const TiledGrid& other) const;
  // Bounds of the allocated tile area in cells: [min, max) on each axis; empty grid gives min == max.
  CellIndex minCell() const { return {tile_x0_ * kTileSize, tile_y0_ * kTileSize}; }
  CellIndex maxCell() const { return {(tile_x0_ + tiles_w_) * kTileSize, (tile_y0_ + tiles_h_) * kTileSize}; }

 private:
  static const GridCell kEmptyCell;
  void growToInclude(int tx, int ty);

  double resolution_;
  double inverse_resolution_;
  int tile_x0_ = 0;  // tile coordinates of tiles_[0]
  int tile_y0_ = 0;
  int tiles_w_ = 0;
  int tiles_h_ = 0;
  std::vector<std::shared_ptr<Tile>> tiles_;  // row-major, tiles_h_ rows of tiles_w_
};

}  // namespace ogf::slam
