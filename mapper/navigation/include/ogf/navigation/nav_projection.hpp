// The 2-D navigation grid of a 3-D map, kept up to date cell by cell: it is told each cell's state after an
// update (what the mapper publishes: quantised predictive probability, class, variance), keeps the band's
// cells (NavBand) of every column in tiles of kTileSize × kTileSize columns, and reclassifies the columns a
// change touched (column_rule.hpp). It answers with the tiles whose columns changed, a column, a tile's
// values, the whole grid as a dense rectangle, and the checksum of the grid (nav_grid.hpp), which it keeps
// up to date per change.
//
// Memory: 2 bytes per band layer per column of a touched tile, plus 2 bytes per column.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/core/cell_key.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "ogf/navigation/column_rule.hpp"
#include "ogf/navigation/nav_band.hpp"
#include "ogf/navigation/nav_grid.hpp"

namespace ogf::navigation {

inline constexpr std::int32_t kTileSize = 32;

struct TileKey {
  std::int32_t x = 0;  // the tile holds columns [x·kTileSize, (x+1)·kTileSize) × [y·kTileSize, (y+1)·kTileSize)
  std::int32_t y = 0;
  friend constexpr bool operator==(const TileKey&, const TileKey&) = default;
  friend constexpr auto operator<=>(const TileKey&, const TileKey&) = default;
};

inline constexpr std::size_t kTileColumns = static_cast<std::size_t>(kTileSize) * kTileSize;

TileKey tileOf(const ColumnKey& column);
// The column at `slot` of `tile`, its values' row-major place from the tile's south-west column.
ColumnKey columnAt(const TileKey& tile, std::size_t slot);

// The most columns a dense grid holds: 2^28, 512 MB of costs and classes, a square of 1.6 km at 0.1 m.
inline constexpr std::int64_t kMaxDenseColumns = std::int64_t{1} << 28;

// The dense rectangle over the known columns of `tiles` (anything with knownTiles() and
// tileValues(tile, cost, class): NavProjection, NavReceiver), row 0 the southernmost; width 0 when no column
// is known. A resource error when the rectangle would hold more than kMaxDenseColumns (known columns far
// apart, as a forged or damaged message can place them): such a grid is followed tile by tile.
template <class Tiles>
Result<NavGrid> denseGrid(double resolution, const NavBand& band, const Tiles& tiles,
                          std::int64_t max_columns = kMaxDenseColumns);

// A 3-D cell's state as the projection reads it.
struct CellState {
  CellKey key;
  double probability = 0.5;  // predictive, [0, 1]
  std::int8_t cell_class = kClassUnknown;
  float variance = 0.0f;
};

class NavProjection {
 public:
  // Error when the band does not validate at `resolution` (NavBand::validate).
  static Result<NavProjection> create(double resolution, const NavBand& band);
  ~NavProjection();
  NavProjection(NavProjection&&) noexcept;
  NavProjection& operator=(NavProjection&&) noexcept;
  NavProjection(const NavProjection&) = delete;
  NavProjection& operator=(const NavProjection&) = delete;

  // Cells after an update; cells outside the band are ignored. Columns they touch are reclassified by the
  // next refresh().
  void update(std::span<const CellState> cells);
  void update(const CellState& cell);
  // Reclassifies the touched columns; the tiles in which a column's cost or class changed, sorted.
  std::vector<TileKey> refresh();
  // Forgets every cell (a new map).
  void clear();

  // The column's current value (as of the last refresh()); unknown for a column never touched.
  NavColumn column(const ColumnKey& key) const;
  // The tiles holding at least one known column, sorted.
  std::vector<TileKey> knownTiles() const;
  // The kTileSize² values of a tile, row-major from its south-west column (nav_grid_t's layout): cost and
  // class spans must hold kTileSize² values.
  void tileValues(const TileKey& tile, std::span<std::int8_t> cost, std::span<std::int8_t> column_class) const;
  // The dense rectangle over every known column (empty grid, width 0, when none is); denseGrid's error when
  // it would be too large.
  Result<NavGrid> grid() const;

  std::uint64_t checksum() const { return checksum_; }
  std::size_t knownColumns() const { return known_columns_; }
  std::size_t tiles() const { return tiles_.size(); }
  double resolution() const { return resolution_; }
  const NavBand& band() const { return band_; }
  const LayerRange& layers() const { return layers_; }

 private:
  NavProjection(double resolution, const NavBand& band);
  struct Tile;
  struct TileKeyHash {
    std::size_t operator()(const TileKey& k) const noexcept;
  };
  Tile& tileAt(const TileKey& key);

  double resolution_;
  NavBand band_;
  LayerRange layers_;
  std::int32_t free_layers_needed_;
  std::unordered_map<TileKey, std::unique_ptr<Tile>, TileKeyHash> tiles_;
  // The tiles with columns to reclassify (each once; Tile::dirty says which columns): a 0.1 m scan
  // updates a million band cells, a dozen per column, so a list of touched columns would be sorted down
  // to a twelfth of itself every scan.
  std::vector<std::pair<TileKey, Tile*>> dirty_tiles_;
  // The tile of the last update (cells come block by block, and a tile holds whole blocks' columns).
  TileKey last_key_{};
  Tile* last_tile_ = nullptr;
  std::uint64_t checksum_ = 0;
  std::size_t known_columns_ = 0;
};

template <class Tiles>
Result<NavGrid> denseGrid(double resolution, const NavBand& band, const Tiles& tiles, std::int64_t max_columns) {
  NavGrid g;
  g.resolution = resolution;
  g.band = band;
  std::vector<std::int8_t> cost(kTileColumns), column_class(kTileColumns);
  const auto known_tiles = tiles.knownTiles();
  // Calls `use(column, cost, class)` for each known column.
  const auto forKnown = [&](auto&& use) {
    for (const auto& tile : known_tiles) {
      tiles.tileValues(tile, cost, column_class);
      for (std::size_t slot = 0; slot < kTileColumns; ++slot)
        if (column_class[slot] != kClassUnknown) use(columnAt(tile, slot), cost[slot], column_class[slot]);
    }
  };
  bool any = false;
  ColumnKey lo, hi;
  forKnown([&](const ColumnKey& c, std::int8_t, std::int8_t) {
    lo = any ? ColumnKey{std::min(lo.x, c.x), std::min(lo.y, c.y)} : c;
    hi = any ? ColumnKey{std::max(hi.x, c.x), std::max(hi.y, c.y)} : c;
    any = true;
  });
  if (!any) return g;
  // In 64 bits: columns far apart span more than an int32.
  const std::int64_t width = std::int64_t{hi.x} - lo.x + 1;
  const std::int64_t height = std::int64_t{hi.y} - lo.y + 1;
  if (width > max_columns / height) {
    return Error::resource("the known columns of the navigation grid span " + std::to_string(width) + " × " +
                           std::to_string(height) + " columns, more than the dense grid's limit of " +
                           std::to_string(max_columns));
  }
  g.origin = lo;
  g.width = static_cast<std::int32_t>(width);
  g.height = static_cast<std::int32_t>(height);
  const auto n = static_cast<std::size_t>(width * height);
  g.cost.assign(n, kUnknownCost);
  g.column_class.assign(n, kClassUnknown);
  forKnown([&](const ColumnKey& c, std::int8_t v, std::int8_t cls) {
    const auto i = g.index(c.x - lo.x, c.y - lo.y);
    g.cost[i] = v;
    g.column_class[i] = cls;
  });
  return g;
}

}  // namespace ogf::navigation
