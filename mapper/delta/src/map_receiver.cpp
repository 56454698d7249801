#include "ogf/delta/map_receiver.hpp"

namespace ogf::delta {
namespace {

// 2^16 parts of 3300 cells is 216 M cells, far beyond any map one mapper keeps; the bound caps what a
// corrupt part_count can make a client allocate.
constexpr std::int32_t kMaxParts = 1 << 16;
// Sequence numbers count updates from 0; 2^62 is beyond any mapper's life and keeps seq + 1 inside int64
// (a keyframe claiming INT64_MAX made the next-update lookup overflow; found by fuzz_map_delta_stream).
constexpr std::int64_t kMaxSeq = std::int64_t{1} << 62;

}  // namespace

bool MapReceiver::wellFormed(const ogf::map_delta_t& m) {
  if (m.kind != ogf::map_delta_t::KIND_DELTA && m.kind != ogf::map_delta_t::KIND_KEYFRAME) return false;
  if (m.part_count < 1 || m.part_count > kMaxParts || m.part_index < 0 || m.part_index >= m.part_count) return false;
  if (m.seq < 0 || m.seq >= kMaxSeq || !(m.resolution > 0.0)) return false;
  const auto n = static_cast<std::size_t>(m.num_cells);
  return m.num_cells >= 0 && m.key_x.size() == n && m.key_y.size() == n && m.key_z.size() == n &&
         m.probability.size() == n && m.cell_class.size() == n && m.variance.size() == n;
}

bool MapReceiver::addPart(std::map<std::int64_t, Assembly>& table, const ogf::map_delta_t& m) {
  Assembly& a = table[m.seq];
  if (a.part_count == 0) {
    a.kind = m.kind;
    a.map_id = m.map_id;
    a.part_count = m.part_count;
    a.checksum = static_cast<std::uint64_t>(m.map_checksum);
  } else if (a.part_count != m.part_count || a.map_id != m.map_id) {
    return false;
  }
  if (a.parts.count(m.part_index) != 0) return true;  // duplicate part
  auto& cells = a.parts[m.part_index];
  cells.reserve(m.key_x.size());
  for (std::size_t i = 0; i < m.key_x.size(); ++i) {
    cells.push_back({{m.key_x[i], m.key_y[i], m.key_z[i]}, m.probability[i], m.cell_class[i], m.variance[i]});
  }
  return true;
}

void MapReceiver::applyKeyframe(std::int64_t seq, Assembly& a) {
  map_.clear();
  for (const auto& [index, part] : a.parts)
    for (const PublishedCell& c : part) map_.set(c);
  applied_seq_ = seq;
  map_id_ = a.map_id;
  server_checksum_ = a.checksum;
  need_keyframe_ = false;
  ++keyframes_applied_;
  // Everything at or before the keyframe is in it. `a` is among the keyframes erased here, so nothing of it
  // is read after (its map id was read after the erase, a use after free found by fuzz_map_delta_stream).
  const std::int64_t map_id = a.map_id;
  for (auto it = keyframes_.begin(); it != keyframes_.end() && it->first <= seq;) it = keyframes_.erase(it);
  for (auto it = deltas_.begin(); it != deltas_.end() && it->first <= seq;) it = deltas_.erase(it);
  for (auto it = deltas_.begin(); it != deltas_.end();) {
    it = (it->second.map_id != map_id) ? deltas_.erase(it) : std::next(it);
  }
}

MapReceiver::Outcome MapReceiver::drain() {
  bool applied = false;
  while (!need_keyframe_) {
    auto next = deltas_.find(applied_seq_ + 1);
    if (next != deltas_.end() && next->second.complete()) {
      for (const auto& [index, part] : next->second.parts)
        for (const PublishedCell& c : part) {
          map_.set(c);
          if (cell_sink_) cell_sink_(c);
        }
      server_checksum_ = next->second.checksum;
      applied_seq_ = next->first;
      deltas_.erase(next);
      applied = true;
      continue;
    }
    // Is a later update already complete? Then the next one's parts are lost.
    for (const auto& [seq, a] : deltas_) {
      if (seq > applied_seq_ + 1 && a.complete()) {
        need_keyframe_ = true;
        ++gaps_;
        return Outcome::kGap;
      }
    }
    break;
  }
  return applied ? Outcome::kApplied : Outcome::kPartial;
}

void MapReceiver::trim() {
  while (deltas_.size() > max_buffered_) deltas_.erase(deltas_.begin());
  while (keyframes_.size() > 4) keyframes_.erase(keyframes_.begin());
}

MapReceiver::Outcome MapReceiver::accept(const ogf::map_delta_t& m) {
  if (!wellFormed(m)) {
    ++malformed_;
    return Outcome::kMalformed;
  }
  if (m.kind == ogf::map_delta_t::KIND_KEYFRAME) {
    if (map_id_ && *map_id_ == m.map_id && !need_keyframe_ && m.seq <= applied_seq_) return Outcome::kStale;
    if (!addPart(keyframes_, m)) {
      ++malformed_;
      keyframes_.erase(m.seq);
      return Outcome::kMalformed;
    }
    Assembly& a = keyframes_[m.seq];
    if (!a.complete()) {
      trim();
      return Outcome::kPartial;
    }
    resolution_ = m.resolution;
    applyKeyframe(m.seq, a);
    drain();  // buffered deltas after the keyframe
    return need_keyframe_ ? Outcome::kGap : Outcome::kKeyframeApplied;
  }

  // A delta.
  if (map_id_ && *map_id_ != m.map_id && !need_keyframe_) {
    // The mapper started a new map (restart): only a keyframe can tell us its state.
    need_keyframe_ = true;
    ++gaps_;
    deltas_.clear();
  }
  if (!need_keyframe_ && m.seq <= applied_seq_) return Outcome::kStale;
  if (m.base_seq != m.seq - 1) {
    ++malformed_;
    return Outcome::kMalformed;
  }
  if (!addPart(deltas_, m)) {
    ++malformed_;
    deltas_.erase(m.seq);
    return Outcome::kMalformed;
  }
  trim();
  if (need_keyframe_) return Outcome::kBuffered;
  return drain();
}

std::string toString(MapReceiver::Outcome o) {
  switch (o) {
    case MapReceiver::Outcome::kApplied: return "applied";
    case MapReceiver::Outcome::kPartial: return "partial";
    case MapReceiver::Outcome::kBuffered: return "buffered";
    case MapReceiver::Outcome::kKeyframeApplied: return "keyframe applied";
    case MapReceiver::Outcome::kGap: return "gap";
    case MapReceiver::Outcome::kStale: return "stale";
    case MapReceiver::Outcome::kMalformed: return "malformed";
  }
  return "?";
}

}  // namespace ogf::delta
