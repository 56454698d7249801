#include "ogf/delta/map_receiver.hpp"

namespace ogf::delta {
namespace {

// 2^16 parts of 3300 cells is 216 M cells, far beyond any map one mapper keeps; the bound caps what a
// corrupt part_count can make a client allocate.
constexpr std::int32_t kMaxParts = 1 << 16;
// Sequence numbers count updates from 0; 2^62 is beyond any mapper's life and keeps seq + 1 inside int64
// (a keyframe claiming INT64_MAX made the next-update lookup overflow; found by fuzz_map_delta_stream).
constexpr std::int64_t kMaxSeq = std::int64_t{1} << 62;
// What a held part takes besides its cells: its node in the assembly and the vector's header.
constexpr std::size_t kPartOverheadBytes = 96;

}  // namespace

bool MapReceiver::wellFormed(const ogf::map_delta_t& m) {
  if (m.kind != ogf::map_delta_t::KIND_DELTA && m.kind != ogf::map_delta_t::KIND_KEYFRAME) return false;
  if (m.part_count < 1 || m.part_count > kMaxParts || m.part_index < 0 || m.part_index >= m.part_count) return false;
  if (m.seq < 0 || m.seq >= kMaxSeq || !(m.resolution > 0.0)) return false;
  const auto n = static_cast<std::size_t>(m.num_cells);
  return m.num_cells >= 0 && m.key_x.size() == n && m.key_y.size() == n && m.key_z.size() == n &&
         m.probability.size() == n && m.cell_class.size() == n && m.variance.size() == n;
}

std::size_t MapReceiver::appliedBytes() const { return map_.size() * sizeof(PublishedCell); }

void MapReceiver::applyKeyframe(const Sequence::Assembly& a) {
  resolution_ = a.meta;
  map_.clear();
  for (const auto& [index, part] : a.parts)
    for (const PublishedCell& c : part) map_.set(c);
}

void MapReceiver::applyUpdate(const Sequence::Assembly& a) {
  for (const auto& [index, part] : a.parts)
    for (const PublishedCell& c : part) {
      map_.set(c);
      if (cell_sink_) cell_sink_(c);
    }
}

MapReceiver::Outcome MapReceiver::accept(const ogf::map_delta_t& m) {
  if (!wellFormed(m)) return sequence_.countMalformed();
  const PartPlace place{m.kind == ogf::map_delta_t::KIND_KEYFRAME, m.map_id, m.seq, m.base_seq, m.part_index,
                        m.part_count, static_cast<std::uint64_t>(m.map_checksum)};
  const auto cells = [&m] {
    std::vector<PublishedCell> out;
    out.reserve(m.key_x.size());
    for (std::size_t i = 0; i < m.key_x.size(); ++i)
      out.push_back({{m.key_x[i], m.key_y[i], m.key_z[i]}, m.probability[i], m.cell_class[i], m.variance[i]});
    return out;
  };
  const std::size_t bytes = kPartOverheadBytes + m.key_x.size() * sizeof(PublishedCell);
  return sequence_.accept(place, m.resolution, cells, *this, bytes);
}

std::string toString(SequenceOutcome o) {
  switch (o) {
    case SequenceOutcome::kApplied: return "applied";
    case SequenceOutcome::kPartial: return "partial";
    case SequenceOutcome::kBuffered: return "buffered";
    case SequenceOutcome::kKeyframeApplied: return "keyframe applied";
    case SequenceOutcome::kGap: return "gap";
    case SequenceOutcome::kStale: return "stale";
    case SequenceOutcome::kMalformed: return "malformed";
    case SequenceOutcome::kDropped: return "dropped";
  }
  return "?";
}

}  // namespace ogf::delta
