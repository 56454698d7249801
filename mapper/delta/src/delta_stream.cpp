#include "ogf/delta/delta_stream.hpp"

#include <algorithm>

namespace ogf::delta {

DeltaStream::DeltaStream(const DeltaStreamConfig& config) : config_(config) {
  config_.max_cells_per_message =
      std::clamp(config_.max_cells_per_message, 1, ogf::messages::kMaxDeltaCellsPerMessage);
}

std::vector<ogf::map_delta_t> DeltaStream::update(std::int64_t utime, std::span<const PublishedCell> candidates) {
  changed_.clear();
  for (const PublishedCell& c : candidates) {
    if (map_.setIfVisiblyDiffers(c)) changed_.push_back(c);
  }
  ++seq_;
  return split(utime, ogf::map_delta_t::KIND_DELTA, seq_ - 1, changed_);
}

std::vector<ogf::map_delta_t> DeltaStream::keyframe(std::int64_t utime, std::span<const PublishedCell> held) const {
  auto cells = map_.sortedCells();
  if (!held.empty()) {
    const auto middle = static_cast<std::ptrdiff_t>(cells.size());
    cells.insert(cells.end(), held.begin(), held.end());
    const auto byKey = [](const PublishedCell& a, const PublishedCell& b) { return a.key < b.key; };
    std::sort(cells.begin() + middle, cells.end(), byKey);
    std::inplace_merge(cells.begin(), cells.begin() + middle, cells.end(), byKey);
  }
  return split(utime, ogf::map_delta_t::KIND_KEYFRAME, -1, cells);
}

void DeltaStream::reset(std::span<const PublishedCell> cells, std::int64_t seq) {
  seq_ = seq;
  map_.clear();
  for (const PublishedCell& c : cells) map_.set(c);
}

std::vector<ogf::map_delta_t> DeltaStream::split(std::int64_t utime, std::int8_t kind, std::int64_t base_seq,
                                                 std::span<const PublishedCell> cells) const {
  const std::size_t per = static_cast<std::size_t>(config_.max_cells_per_message);
  const std::size_t parts = std::max<std::size_t>(1, (cells.size() + per - 1) / per);
  std::vector<ogf::map_delta_t> out(parts);
  for (std::size_t p = 0; p < parts; ++p) {
    ogf::map_delta_t& m = out[p];
    m.utime = utime;
    m.map_id = config_.map_id;
    m.seq = seq_;
    m.base_seq = base_seq;
    m.kind = kind;
    m.part_index = static_cast<std::int32_t>(p);
    m.part_count = static_cast<std::int32_t>(parts);
    m.resolution = config_.resolution;
    m.map_checksum = static_cast<std::int64_t>(map_.checksum());
    const std::size_t begin = p * per;
    const std::size_t end = std::min(cells.size(), begin + per);
    const auto n = end - begin;
    m.num_cells = static_cast<std::int32_t>(n);
    m.key_x.resize(n);
    m.key_y.resize(n);
    m.key_z.resize(n);
    m.probability.resize(n);
    m.cell_class.resize(n);
    m.variance.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const PublishedCell& c = cells[begin + i];
      m.key_x[i] = c.key.x;
      m.key_y[i] = c.key.y;
      m.key_z[i] = c.key.z;
      m.probability[i] = c.probability;
      m.cell_class[i] = c.cell_class;
      m.variance[i] = c.variance;
    }
  }
  return out;
}

}  // namespace ogf::delta
