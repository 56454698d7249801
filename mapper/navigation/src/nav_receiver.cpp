#include "ogf/navigation/nav_receiver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace ogf::navigation {
namespace {

constexpr std::size_t kTileColumns = static_cast<std::size_t>(kTileSize) * kTileSize;
// 2^14 parts of 24 tiles of 32² columns is 400 M columns, beyond any grid a mapper keeps; the bound caps what
// a corrupt part_count can make a client allocate.
constexpr std::int32_t kMaxParts = 1 << 14;
// Sequence numbers count updates from 0; 2^62 keeps seq + 1 inside int64.
constexpr std::int64_t kMaxSeq = std::int64_t{1} << 62;
// Tiles one message may carry: a datagram holds 24; more is not a message the mapper sends.
constexpr std::int32_t kMaxTilesPerPart = 64;

bool validColumn(std::int8_t cost, std::int8_t column_class) {
  if (column_class == kClassUnknown) return cost == kUnknownCost;
  return (column_class == kClassFree || column_class == kClassOccupied) && cost >= 0 && cost <= 100;
}

std::size_t knownIn(const std::vector<std::int8_t>& column_class) {
  return static_cast<std::size_t>(
      std::count_if(column_class.begin(), column_class.end(), [](std::int8_t c) { return c != kClassUnknown; }));
}

ColumnKey columnAt(const TileKey& t, std::size_t slot) {
  return {t.x * kTileSize + static_cast<std::int32_t>(slot % kTileSize),
          t.y * kTileSize + static_cast<std::int32_t>(slot / kTileSize)};
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

bool NavReceiver::addPart(std::map<std::int64_t, Assembly>& table, const ogf::nav_grid_t& m) {
  Assembly& a = table[m.seq];
  if (a.part_count == 0) {
    a.kind = m.kind;
    a.map_id = m.map_id;
    a.part_count = m.part_count;
    a.checksum = static_cast<std::uint64_t>(m.grid_checksum);
    a.resolution = m.resolution;
    a.band.floor_z = m.floor_z;
    a.band.min_height = m.min_height;
    a.band.max_height = m.max_height;
  } else if (a.part_count != m.part_count || a.map_id != m.map_id) {
    return false;
  }
  if (a.parts.count(m.part_index) != 0) return true;  // duplicate part
  auto& tiles = a.parts[m.part_index];
  for (std::size_t t = 0; t < m.tile_x.size(); ++t) {
    const auto from = static_cast<std::ptrdiff_t>(t * kTileColumns);
    const auto to = from + static_cast<std::ptrdiff_t>(kTileColumns);
    tiles.push_back({{m.tile_x[t], m.tile_y[t]},
                     {std::vector<std::int8_t>(m.cost.begin() + from, m.cost.begin() + to),
                      std::vector<std::int8_t>(m.column_class.begin() + from, m.column_class.begin() + to)}});
  }
  return true;
}

void NavReceiver::setTile(const TileKey& key, TileValues values) {
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
  tiles_.emplace(key, std::move(values));
}

void NavReceiver::applyTiles(Assembly& a) {
  for (auto& [index, part] : a.parts)
    for (auto& [key, values] : part) setTile(key, std::move(values));
  resolution_ = a.resolution;
  band_ = a.band;
  server_checksum_ = a.checksum;
}

void NavReceiver::applyKeyframe(std::int64_t seq, Assembly& a) {
  tiles_.clear();
  checksum_ = 0;
  known_columns_ = 0;
  applyTiles(a);
  applied_seq_ = seq;
  map_id_ = a.map_id;
  need_keyframe_ = false;
  ++keyframes_applied_;
  // Everything at or before the keyframe is in it; `a` is erased here, so its map id is read first.
  const std::int64_t map_id = a.map_id;
  for (auto it = keyframes_.begin(); it != keyframes_.end() && it->first <= seq;) it = keyframes_.erase(it);
  for (auto it = updates_.begin(); it != updates_.end() && it->first <= seq;) it = updates_.erase(it);
  for (auto it = updates_.begin(); it != updates_.end();)
    it = (it->second.map_id != map_id) ? updates_.erase(it) : std::next(it);
}

NavReceiver::Outcome NavReceiver::drain() {
  bool applied = false;
  while (!need_keyframe_) {
    auto next = updates_.find(applied_seq_ + 1);
    if (next != updates_.end() && next->second.complete()) {
      applyTiles(next->second);
      applied_seq_ = next->first;
      updates_.erase(next);
      applied = true;
      continue;
    }
    // A later update complete while the next is not: the mapper sends an update's parts back to back, so
    // the missing ones are lost.
    const bool later_complete = std::any_of(updates_.begin(), updates_.end(), [&](const auto& entry) {
      return entry.first > applied_seq_ + 1 && entry.second.complete();
    });
    if (later_complete) {
      need_keyframe_ = true;
      ++gaps_;
      return Outcome::kGap;
    }
    break;
  }
  return applied ? Outcome::kApplied : Outcome::kPartial;
}

void NavReceiver::trim() {
  while (updates_.size() > max_buffered_) updates_.erase(updates_.begin());
  while (keyframes_.size() > 4) keyframes_.erase(keyframes_.begin());
}

NavReceiver::Outcome NavReceiver::accept(const ogf::nav_grid_t& m) {
  if (!wellFormed(m)) {
    ++malformed_;
    return Outcome::kMalformed;
  }
  if (m.kind == ogf::nav_grid_t::KIND_KEYFRAME) {
    if (map_id_ && *map_id_ == m.map_id && !need_keyframe_ && m.seq <= applied_seq_) return Outcome::kStale;
    if (m.base_seq != -1 || !addPart(keyframes_, m)) {
      ++malformed_;
      keyframes_.erase(m.seq);
      return Outcome::kMalformed;
    }
    Assembly& a = keyframes_[m.seq];
    if (!a.complete()) {
      trim();
      return Outcome::kPartial;
    }
    applyKeyframe(m.seq, a);
    drain();
    return need_keyframe_ ? Outcome::kGap : Outcome::kKeyframeApplied;
  }
  if (map_id_ && *map_id_ != m.map_id && !need_keyframe_) {
    // A new map: only a keyframe can tell its grid.
    need_keyframe_ = true;
    ++gaps_;
    updates_.clear();
  }
  if (!need_keyframe_ && m.seq <= applied_seq_) return Outcome::kStale;
  if (m.base_seq != m.seq - 1) {
    ++malformed_;
    return Outcome::kMalformed;
  }
  if (!addPart(updates_, m)) {
    ++malformed_;
    updates_.erase(m.seq);
    return Outcome::kMalformed;
  }
  trim();
  if (need_keyframe_) return Outcome::kBuffered;
  return drain();
}

NavColumn NavReceiver::column(const ColumnKey& key) const {
  const auto t = tileOf(key);
  const auto it = tiles_.find(t);
  if (it == tiles_.end()) return {};
  const auto slot =
      static_cast<std::size_t>(key.y - t.y * kTileSize) * kTileSize + static_cast<std::size_t>(key.x - t.x * kTileSize);
  return {it->second.cost[slot], it->second.column_class[slot]};
}

NavGrid NavReceiver::grid() const {
  NavGrid g;
  g.resolution = resolution_;
  g.band = band_;
  if (known_columns_ == 0) return g;
  constexpr auto kMax = std::numeric_limits<std::int32_t>::max();
  constexpr auto kMin = std::numeric_limits<std::int32_t>::min();
  ColumnKey lo{kMax, kMax}, hi{kMin, kMin};
  for (const auto& [key, values] : tiles_)
    for (std::size_t slot = 0; slot < kTileColumns; ++slot) {
      if (values.column_class[slot] == kClassUnknown) continue;
      const auto c = columnAt(key, slot);
      lo = {std::min(lo.x, c.x), std::min(lo.y, c.y)};
      hi = {std::max(hi.x, c.x), std::max(hi.y, c.y)};
    }
  g.origin = lo;
  g.width = hi.x - lo.x + 1;
  g.height = hi.y - lo.y + 1;
  const auto n = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
  g.cost.assign(n, kUnknownCost);
  g.column_class.assign(n, kClassUnknown);
  for (const auto& [key, values] : tiles_)
    for (std::size_t slot = 0; slot < kTileColumns; ++slot) {
      if (values.column_class[slot] == kClassUnknown) continue;
      const auto c = columnAt(key, slot);
      const auto i = g.index(c.x - lo.x, c.y - lo.y);
      g.cost[i] = values.cost[slot];
      g.column_class[i] = values.column_class[slot];
    }
  return g;
}

std::string toString(NavReceiver::Outcome o) {
  switch (o) {
    case NavReceiver::Outcome::kApplied: return "applied";
    case NavReceiver::Outcome::kPartial: return "partial";
    case NavReceiver::Outcome::kBuffered: return "buffered";
    case NavReceiver::Outcome::kKeyframeApplied: return "keyframe applied";
    case NavReceiver::Outcome::kGap: return "gap";
    case NavReceiver::Outcome::kStale: return "stale";
    case NavReceiver::Outcome::kMalformed: return "malformed";
  }
  return "?";
}

}  // namespace ogf::navigation
