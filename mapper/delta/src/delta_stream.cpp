#include "ogf/delta/delta_stream.hpp"

#include <algorithm>

namespace ogf::delta {

DeltaStream::DeltaStream(const DeltaStreamConfig& config) : config_(config) {
  config_.max_cells_per_message =
      std::clamp(config_.max_cells_per_message, 1, ogf::messages::kMaxDeltaCellsPerMessage);
}

std::vector<ogf::map_delta_t> DeltaStream::update(std::int64_t utime, std::span<const PublishedCell> candidates) {
  changed_.clear();
  // Candidates come in runs of one slab: each new slab's slot is asked for kAhead candidates ahead, so
  // its look-up finds it in cache.
  constexpr std::size_t kAhead = 128;
  const std::size_t n = candidates.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) {
      const CellKey& next = candidates[i + kAhead].key;
      if (!(PublishedBlock::blockKeyOf(next) == PublishedBlock::blockKeyOf(candidates[i + kAhead - 1].key))) {
        map_.prefetch(next);
      }
    }
    if (map_.setIfVisiblyDiffers(candidates[i])) changed_.push_back(candidates[i]);
  }
  ++seq_;
  return split(utime, ogf::map_delta_t::KIND_DELTA, seq_ - 1, changed_);
}

std::vector<ogf::map_delta_t> DeltaStream::keyframe(std::int64_t utime) const {
  return split(utime, ogf::map_delta_t::KIND_KEYFRAME, -1, map_.sortedCells());
}

void DeltaStream::reset(std::span<const PublishedCell> cells, std::int64_t seq) {
  seq_ = seq;
  map_.clear();
  for (const PublishedCell& c : cells) map_.set(c);
}

ogf::map_delta_t makePart(const PartHeader& header, std::int32_t index, std::span<const PublishedCell> cells) {
  ogf::map_delta_t m{};
  m.utime = header.utime;
  m.map_id = header.map_id;
  m.seq = header.seq;
  m.base_seq = header.base_seq;
  m.kind = header.kind;
  m.part_index = index;
  m.part_count = header.part_count;
  m.resolution = header.resolution;
  m.map_checksum = header.checksum;
  const std::size_t n = cells.size();
  m.num_cells = static_cast<std::int32_t>(n);
  m.key_x.resize(n);
  m.key_y.resize(n);
  m.key_z.resize(n);
  m.probability.resize(n);
  m.cell_class.resize(n);
  m.variance.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const PublishedCell& c = cells[i];
    m.key_x[i] = c.key.x;
    m.key_y[i] = c.key.y;
    m.key_z[i] = c.key.z;
    m.probability[i] = c.probability;
    m.cell_class[i] = c.cell_class;
    m.variance[i] = c.variance;
  }
  return m;
}

PartHeader DeltaStream::header(std::int64_t utime, std::int8_t kind, std::int64_t base_seq, std::size_t cells) const {
  const auto per = static_cast<std::size_t>(config_.max_cells_per_message);
  return {utime,
          config_.map_id,
          seq_,
          base_seq,
          kind,
          config_.resolution,
          static_cast<std::int64_t>(map_.checksum()),
          static_cast<std::int32_t>(std::max<std::size_t>(1, (cells + per - 1) / per))};
}

std::vector<ogf::map_delta_t> DeltaStream::split(std::int64_t utime, std::int8_t kind, std::int64_t base_seq,
                                                 std::span<const PublishedCell> cells) const {
  const std::size_t per = static_cast<std::size_t>(config_.max_cells_per_message);
  const PartHeader head = header(utime, kind, base_seq, cells.size());
  const auto parts = static_cast<std::size_t>(head.part_count);
  std::vector<ogf::map_delta_t> out;
  out.reserve(parts);
  for (std::size_t p = 0; p < parts; ++p) {
    const std::size_t begin = p * per;
    out.push_back(makePart(head, static_cast<std::int32_t>(p),
                           cells.subspan(begin, std::min(cells.size(), begin + per) - begin)));
  }
  return out;
}

}  // namespace ogf::delta
