#include "ogf/navigation/nav_receiver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace ogf::navigation {
namespace {

// 2^14 parts of 24 tiles of 32² columns is 400 M columns, beyond any grid a mapper keeps; the bound caps what
// a corrupt part_count can make a client allocate.
constexpr std::int32_t kMaxParts = 1 << 14;
// Sequence numbers count updates from 0; 2^62 keeps seq + 1 inside int64.
constexpr std::int64_t kMaxSeq = std::int64_t{1} << 62;
// Tiles one message may carry: a datagram holds 24; more is not a message the mapper sends.
constexpr std::int32_t kMaxTilesPerPart = 64;
// What a tile takes held: its two arrays of kTileSize² values, their headers and its key, in a node.
constexpr std::size_t kTileBytes = 2 * kTileColumns + 96;
// What a held part takes besides its tiles.
constexpr std::size_t kPartOverheadBytes = 96;

bool validColumn(std::int8_t cost, std::int8_t column_class) {
  if (column_class == kClassUnknown) return cost == kUnknownCost;
  return (column_class == kClassFree || column_class == kClassOccupied) && cost >= 0 && cost <= 100;
}

std::size_t knownIn(const std::vector<std::int8_t>& column_class) {
  return static_cast<std::size_t>(
      std::count_if(column_class.begin(), column_class.end(), [](std::int8_t c) { return c != kClassUnknown; }));
}

}  // namespace

bool NavReceiver::wellFormed(const ogf::nav_grid_t& m) {
  if (m.kind != ogf::nav_grid_t::KIND_UPDATE && m.kind != ogf::nav_grid_t::KIND_KEYFRAME) return false;
  if (m.part_count < 1 || m.part_count > kMaxParts || m.part_index < 0 || m.part_index >= m.part_count) return false;
  if (m.seq < 0 || m.seq >= kMaxSeq || !(m.resolution > 0.0) || !std::isfinite(m.resolution)) return false;
  if (!std::isfinite(m.floor_z) || !std::isfinite(m.min_height) || !std::isfinite(m.max_height)) return false;
  if (m.tile_size != kTileSize || m.num_tiles < 0 || m.num_tiles > kMaxTilesPerPart) return false;
  const auto tiles = static_cast<std::size_t>(m.num_tiles);
  if (m.tile_x.size() != tiles || m.tile_y.size() != tiles) return false;
  // A tile's columns must be ColumnKeys (int32): beyond, tile × kTileSize overflows.
  constexpr std::int32_t kMaxTile = std::numeric_limits<std::int32_t>::max() / kTileSize - 1;
  for (std::size_t t = 0; t < tiles; ++t)
    if (std::abs(static_cast<std::int64_t>(m.tile_x[t])) > kMaxTile ||
        std::abs(static_cast<std::int64_t>(m.tile_y[t])) > kMaxTile)
      return false;
  if (m.num_columns < 0 || static_cast<std::size_t>(m.num_columns) != tiles * kTileColumns) return false;
  if (m.cost.size() != tiles * kTileColumns || m.column_class.size() != tiles * kTileColumns) return false;
  for (std::size_t i = 0; i < m.cost.size(); ++i)
    if (!validColumn(m.cost[i], m.column_class[i])) return false;
  return true;
}

std::size_t NavReceiver::appliedBytes() const { return tiles_.size() * kTileBytes; }

void NavReceiver::setTile(const TileKey& key, const TileValues& values) {
  const auto it = tiles_.find(key);
  if (it != tiles_.end()) {
    for (std::size_t slot = 0; slot < kTileColumns; ++slot) {
      if (it->second.column_class[slot] == kClassUnknown) continue;
      checksum_ -= columnChecksum(columnAt(key, slot), {it->second.cost[slot], it->second.column_class[slot]});
    }
    known_columns_ -= knownIn(it->second.column_class);
    tiles_.erase(it);
  }
  const auto known = knownIn(values.column_class);
  if (known == 0) return;
  for (std::size_t slot = 0; slot < kTileColumns; ++slot) {
    if (values.column_class[slot] == kClassUnknown) continue;
    checksum_ += columnChecksum(columnAt(key, slot), {values.cost[slot], values.column_class[slot]});
  }
  known_columns_ += known;
  tiles_.emplace(key, values);
}

void NavReceiver::applyUpdate(const Sequence::Assembly& a) {
  for (const auto& [index, part] : a.parts)
    for (const auto& [key, values] : part) setTile(key, values);
  meta_ = a.meta;
}

void NavReceiver::applyKeyframe(const Sequence::Assembly& a) {
  tiles_.clear();
  checksum_ = 0;
  known_columns_ = 0;
  applyUpdate(a);
}

NavReceiver::Outcome NavReceiver::accept(const ogf::nav_grid_t& m) {
  const bool keyframe = m.kind == ogf::nav_grid_t::KIND_KEYFRAME;
  if (!wellFormed(m) || (keyframe && m.base_seq != -1)) return sequence_.countMalformed();
  const delta::PartPlace place{keyframe, m.map_id, m.seq, m.base_seq, m.part_index, m.part_count,
                               static_cast<std::uint64_t>(m.grid_checksum)};
  GridMeta meta{m.resolution, {}};
  meta.band.floor_z = m.floor_z;
  meta.band.min_height = m.min_height;
  meta.band.max_height = m.max_height;
  const auto tiles = [&m] {
    std::vector<std::pair<TileKey, TileValues>> out;
    for (std::size_t t = 0; t < m.tile_x.size(); ++t) {
      const auto from = static_cast<std::ptrdiff_t>(t * kTileColumns);
      const auto to = from + static_cast<std::ptrdiff_t>(kTileColumns);
      out.push_back({{m.tile_x[t], m.tile_y[t]},
                     {std::vector<std::int8_t>(m.cost.begin() + from, m.cost.begin() + to),
                      std::vector<std::int8_t>(m.column_class.begin() + from, m.column_class.begin() + to)}});
    }
    return out;
  };
  return sequence_.accept(place, meta, tiles, *this, kPartOverheadBytes + m.tile_x.size() * kTileBytes);
}

NavColumn NavReceiver::column(const ColumnKey& key) const {
  const auto t = tileOf(key);
  const auto it = tiles_.find(t);
  if (it == tiles_.end()) return {};
  const auto slot =
      static_cast<std::size_t>(key.y - t.y * kTileSize) * kTileSize + static_cast<std::size_t>(key.x - t.x * kTileSize);
  return {it->second.cost[slot], it->second.column_class[slot]};
}

Result<NavGrid> NavReceiver::grid(std::int64_t max_columns) const {
  return denseGrid(meta_.resolution, meta_.band, *this, max_columns);
}

std::vector<TileKey> NavReceiver::knownTiles() const {
  std::vector<TileKey> out;
  out.reserve(tiles_.size());
  for (const auto& [key, values] : tiles_) out.push_back(key);
  return out;
}

void NavReceiver::tileValues(const TileKey& tile, std::span<std::int8_t> cost,
                             std::span<std::int8_t> column_class) const {
  const auto it = tiles_.find(tile);
  if (it == tiles_.end()) {
    std::fill(cost.begin(), cost.begin() + kTileColumns, kUnknownCost);
    std::fill(column_class.begin(), column_class.begin() + kTileColumns, kClassUnknown);
    return;
  }
  std::copy(it->second.cost.begin(), it->second.cost.end(), cost.begin());
  std::copy(it->second.column_class.begin(), it->second.column_class.end(), column_class.begin());
}

}  // namespace ogf::navigation
