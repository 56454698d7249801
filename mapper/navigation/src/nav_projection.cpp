#include "ogf/navigation/nav_projection.hpp"

#include <algorithm>
#include <array>
#include <limits>

namespace ogf::navigation {
namespace {

std::int32_t floorDiv(std::int32_t a, std::int32_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The column's place in its tile: row-major from the tile's south-west column.
std::size_t slotOf(const ColumnKey& c) {
  const auto t = tileOf(c);
  return static_cast<std::size_t>(c.y - t.y * kTileSize) * kTileSize + static_cast<std::size_t>(c.x - t.x * kTileSize);
}

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
NavProjection::NavProjection(NavProjection&&) noexcept = default;
NavProjection& NavProjection::operator=(NavProjection&&) noexcept = default;

NavProjection::Tile& NavProjection::tileAt(const TileKey& key) {
  auto& slot = tiles_[key];
  if (!slot) slot = std::make_unique<Tile>(layers_.count());
  return *slot;
}

void NavProjection::update(const CellState& cell) {
  if (!layers_.contains(cell.key.z)) return;
  const ColumnKey column{cell.key.x, cell.key.y};
  auto& tile = tileAt(tileOf(column));
  const auto layers = static_cast<std::size_t>(layers_.count());
  tile.cells[slotOf(column) * layers + static_cast<std::size_t>(cell.key.z - layers_.lo)] = {
      cellCost(cell.probability, cell.variance), cell.cell_class};
  touched_.push_back(column);
}

void NavProjection::update(std::span<const CellState> cells) {
  for (const auto& c : cells) update(c);
}

std::vector<TileKey> NavProjection::refresh() {
  std::sort(touched_.begin(), touched_.end());
  touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
  std::vector<TileKey> changed;
  const auto layers = static_cast<std::size_t>(layers_.count());
  for (const auto& column : touched_) {
    const auto key = tileOf(column);
    auto& tile = *tiles_.at(key);
    const auto slot = slotOf(column);
    const auto now = classifyColumn(std::span(tile.cells).subspan(slot * layers, layers), free_layers_needed_);
    auto& was = tile.columns[slot];
    if (now == was) continue;
    if (was.known()) {
      checksum_ -= columnChecksum(column, was);
      --tile.known;
      --known_columns_;
    }
    if (now.known()) {
      checksum_ += columnChecksum(column, now);
      ++tile.known;
      ++known_columns_;
    }
    was = now;
    changed.push_back(key);
  }
  touched_.clear();
  std::sort(changed.begin(), changed.end());
  changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
  return changed;
}

void NavProjection::clear() {
  tiles_.clear();
  touched_.clear();
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

NavGrid NavProjection::grid() const { return denseGrid(resolution_, band_, *this); }

}  // namespace ogf::navigation
