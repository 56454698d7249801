#include "ogf/navigation/nav_projection.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <utility>

namespace ogf::navigation {
namespace {

std::int32_t floorDiv(std::int32_t a, std::int32_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The column's place in its tile `t`: row-major from the tile's south-west column.
std::size_t slotIn(const ColumnKey& c, const TileKey& t) {
  return static_cast<std::size_t>(c.y - t.y * kTileSize) * kTileSize + static_cast<std::size_t>(c.x - t.x * kTileSize);
}
std::size_t slotOf(const ColumnKey& c) { return slotIn(c, tileOf(c)); }

}  // namespace

ColumnKey columnAt(const TileKey& t, std::size_t slot) {
  return {t.x * kTileSize + static_cast<std::int32_t>(slot % kTileSize),
          t.y * kTileSize + static_cast<std::int32_t>(slot / kTileSize)};
}

TileKey tileOf(const ColumnKey& column) { return {floorDiv(column.x, kTileSize), floorDiv(column.y, kTileSize)}; }

struct NavProjection::Tile {
  explicit Tile(std::int32_t layers) : cells(kTileColumns * static_cast<std::size_t>(layers)) {}
  std::vector<BandCell> cells;  // column slot × layers + (z − lowest layer)
  std::array<NavColumn, kTileColumns> columns{};
  std::size_t known = 0;
  std::array<std::uint64_t, (kTileColumns + 63) / 64> dirty{};  // column slots updated since refresh()
  bool listed = false;                                          // in dirty_tiles_
};

std::size_t NavProjection::TileKeyHash::operator()(const TileKey& k) const noexcept {
  std::uint64_t h = static_cast<std::uint32_t>(k.x) * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint32_t>(k.y);
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ULL;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

Result<NavProjection> NavProjection::create(double resolution, const NavBand& band) {
  if (auto st = band.validate(resolution); !st) return st.error();
  return NavProjection(resolution, band);
}

NavProjection::NavProjection(double resolution, const NavBand& band)
    : resolution_(resolution),
      band_(band),
      layers_(band.layers(resolution)),
      free_layers_needed_(band.freeLayersNeeded(resolution)) {}

NavProjection::~NavProjection() = default;
// By hand: the moved-from projection must not keep the pointer to a tile it no longer owns.
NavProjection::NavProjection(NavProjection&& other) noexcept
    : resolution_(other.resolution_),
      band_(other.band_),
      layers_(other.layers_),
      free_layers_needed_(other.free_layers_needed_) {
  *this = std::move(other);
}

NavProjection& NavProjection::operator=(NavProjection&& other) noexcept {
  if (this == &other) return *this;
  resolution_ = other.resolution_;
  band_ = other.band_;
  layers_ = other.layers_;
  free_layers_needed_ = other.free_layers_needed_;
  tiles_ = std::move(other.tiles_);
  other.tiles_.clear();
  dirty_tiles_ = std::move(other.dirty_tiles_);
  other.dirty_tiles_.clear();
  last_key_ = other.last_key_;
  last_tile_ = std::exchange(other.last_tile_, nullptr);
  checksum_ = std::exchange(other.checksum_, 0);
  known_columns_ = std::exchange(other.known_columns_, 0);
  return *this;
}

NavProjection::Tile& NavProjection::tileAt(const TileKey& key) {
  auto& slot = tiles_[key];
  if (!slot) slot = std::make_unique<Tile>(layers_.count());
  return *slot;
}

void NavProjection::update(const CellState& cell) {
  if (!layers_.contains(cell.key.z)) return;
  const ColumnKey column{cell.key.x, cell.key.y};
  const TileKey key = tileOf(column);
  if (last_tile_ == nullptr || !(key == last_key_)) {
    last_key_ = key;
    last_tile_ = &tileAt(key);
  }
  Tile& tile = *last_tile_;
  const auto layers = static_cast<std::size_t>(layers_.count());
  const std::size_t slot = slotIn(column, key);
  tile.cells[slot * layers + static_cast<std::size_t>(cell.key.z - layers_.lo)] = {
      cellCost(cell.probability, cell.variance), cell.cell_class};
  tile.dirty[slot >> 6] |= std::uint64_t{1} << (slot & 63U);
  if (!tile.listed) {
    tile.listed = true;
    dirty_tiles_.emplace_back(key, &tile);
  }
}

void NavProjection::update(std::span<const CellState> cells) {
  for (const auto& c : cells) update(c);
}

std::vector<TileKey> NavProjection::refresh() {
  std::vector<TileKey> changed;
  const auto layers = static_cast<std::size_t>(layers_.count());
  for (auto& [key, tile] : dirty_tiles_) {
    bool any = false;
    for (std::size_t w = 0; w < tile->dirty.size(); ++w) {
      for (std::uint64_t rest = tile->dirty[w]; rest != 0; rest &= rest - 1) {
        const std::size_t slot = w * 64 + static_cast<std::size_t>(std::countr_zero(rest));
        const auto now = classifyColumn(std::span(tile->cells).subspan(slot * layers, layers), free_layers_needed_);
        auto& was = tile->columns[slot];
        if (now == was) continue;
        const ColumnKey column = columnAt(key, slot);
        if (was.known()) {
          checksum_ -= columnChecksum(column, was);
          --tile->known;
          --known_columns_;
        }
        if (now.known()) {
          checksum_ += columnChecksum(column, now);
          ++tile->known;
          ++known_columns_;
        }
        was = now;
        any = true;
      }
    }
    tile->dirty = {};
    tile->listed = false;
    if (any) changed.push_back(key);
  }
  dirty_tiles_.clear();
  std::sort(changed.begin(), changed.end());
  return changed;
}

void NavProjection::clear() {
  tiles_.clear();
  dirty_tiles_.clear();
  last_tile_ = nullptr;
  checksum_ = 0;
  known_columns_ = 0;
}

NavColumn NavProjection::column(const ColumnKey& key) const {
  const auto it = tiles_.find(tileOf(key));
  return it == tiles_.end() ? NavColumn{} : it->second->columns[slotOf(key)];
}

std::vector<TileKey> NavProjection::knownTiles() const {
  std::vector<TileKey> out;
  for (const auto& [key, tile] : tiles_)
    if (tile->known > 0) out.push_back(key);
  std::sort(out.begin(), out.end());
  return out;
}

void NavProjection::tileValues(const TileKey& key, std::span<std::int8_t> cost,
                               std::span<std::int8_t> column_class) const {
  const auto it = tiles_.find(key);
  for (std::size_t slot = 0; slot < kTileColumns; ++slot) {
    const auto c = it == tiles_.end() ? NavColumn{} : it->second->columns[slot];
    cost[slot] = c.cost;
    column_class[slot] = c.column_class;
  }
}

Result<NavGrid> NavProjection::grid() const { return denseGrid(resolution_, band_, *this); }

}  // namespace ogf::navigation
