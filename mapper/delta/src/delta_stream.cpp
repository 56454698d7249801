#include "ogf/delta/delta_stream.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

namespace ogf::delta {

DeltaStream::DeltaStream(const DeltaStreamConfig& config, const PublishingRule& rule) : config_(config), rule_(rule) {
  config_.max_cells_per_message =
      std::clamp(config_.max_cells_per_message, 1, ogf::messages::kMaxDeltaCellsPerMessage);
}

void DeltaStream::prefetchAhead(std::span<const PublishedCell> candidates, std::size_t i) const {
  if (i + kAhead >= candidates.size()) return;
  const CellKey& next = candidates[i + kAhead].key;
  if (!(PublishedBlock::blockKeyOf(next) == PublishedBlock::blockKeyOf(candidates[i + kAhead - 1].key))) map_.prefetch(next);
}

std::vector<ogf::map_delta_t> DeltaStream::update(std::int64_t utime, std::span<const PublishedCell> candidates) {
  changed_.clear();
  figures_ = {};
  if (allowance_ == LinkBudget::kUnbounded && deferred_.empty()) {
    // Everything worth sending goes out now: one look-up per candidate, the cell set on the way.
    const std::int32_t step = rule_.quantisedStep();
    const double variance_step = rule_.variance_step;
    const std::size_t n = candidates.size();
    for (std::size_t i = 0; i < n; ++i) {
      prefetchAhead(candidates, i);
      const PublishedCell& c = candidates[i];
      if (map_.setIf(c, [&](const PublishedCell& published, bool) {
            return worthSending(c, published, step, variance_step) != Worth::kNothing;
          }))
        changed_.push_back(c);
    }
    figures_.worth = changed_.size();
  } else {
    chooseWithin(candidates);
  }
  ++seq_;
  auto out = split(utime, ogf::map_delta_t::KIND_DELTA, seq_ - 1, changed_);
  figures_.sent = changed_.size();
  figures_.deferred = deferred_.size();
  figures_.stale = stale_.size();
  figures_.overflowed = overflowed_ - overflowed_reported_;  // refreshStale's before the update included
  overflowed_reported_ = overflowed_;
  figures_.bytes = bytesOf(out);
  return out;
}

std::pair<Worth, bool> DeltaStream::judge(const PublishedCell& c, std::int32_t step, double variance_step) {
  Worth worth = Worth::kNothing;
  bool present = false;
  map_.setIf(c, [&](const PublishedCell& published, bool was) {
    worth = worthSending(c, published, step, variance_step);
    present = was;
    return false;  // only read
  });
  return {worth, present};
}

void DeltaStream::chooseWithin(std::span<const PublishedCell> candidates) {
  const std::int32_t step = rule_.quantisedStep();
  const double variance_step = rule_.variance_step;
  wanted_.clear();
  chosen_.clear();
  const bool bounded = allowance_ != LinkBudget::kUnbounded;
  std::size_t room = bounded ? cellsWithin(allowance_) : 0;
  if (stale_.empty()) {
    // The class changes this update can place: those it sends and those the waiting set holds (a class
    // change takes a waiting probability move's place). Each class change wanted beyond them, and every
    // change after it, goes to a stale slab whatever comes later, so the rest of the candidates join the
    // stale slabs at once (a fresh map's first scan at 0.1 m has millions of them).
    const std::size_t capacity = deferred_.capacity();
    const std::size_t placeable = capacity > std::numeric_limits<std::size_t>::max() - room ? capacity : room + capacity;
    std::size_t wanted_classes = 0;
    const bool waiting = !deferred_.empty();
    const std::size_t n = candidates.size();
    // A scan's candidates number in the millions at most (each a changed cell of the filter), below 2^32.
    assert(n <= std::numeric_limits<std::uint32_t>::max());
    for (std::size_t i = 0; i < n; ++i) {
      const PublishedCell& c = candidates[i];
      prefetchAhead(candidates, i);
      const auto [worth, present] = judge(c, step, variance_step);
      // A waiting cell takes its newest state and keeps its place (or leaves, back within the step).
      if (waiting && deferred_.refresh(c, worth)) continue;
      if (worth == Worth::kNothing) continue;
      wanted_.push_back({static_cast<std::uint32_t>(i), worth, present});
      if (worth == Worth::kClass && bounded && ++wanted_classes > placeable) {
        joinStale(candidates.subspan(i + 1));
        break;
      }
    }
  } else {
    joinStale(candidates);
  }
  figures_.worth = wanted_.size();
  if (!bounded) room = wanted_.size() + deferred_.size();
  const auto takeWanted = [&](Worth worth) {
    for (const Wanted& w : wanted_) {
      if (w.worth != worth) continue;
      const DeferredCells::Entry e{candidates[w.index], w.worth, w.present};
      if (room > 0) {
        chosen_.push_back(e);
        --room;
      } else {
        wait(e);
      }
    }
  };
  takeDeferred(Worth::kClass, room);
  takeWanted(Worth::kClass);
  takeDeferred(Worth::kProbability, room);
  takeWanted(Worth::kProbability);
  for (const DeferredCells::Entry& e : chosen_) {
    map_.set(e.cell);
    changed_.push_back(e.cell);
  }
}

void DeltaStream::joinStale(std::span<const PublishedCell> candidates) {
  const std::int32_t step = rule_.quantisedStep();
  const double variance_step = rule_.variance_step;
  const bool waiting = !deferred_.empty();
  // The candidates come slab by slab: per run of one slab, which of its cells wait (looked up once) and
  // whether the slab joined the stale ones (after which the rest of the run needs no judgement).
  bool in_run = false;
  CellKey run_slab{};
  std::uint64_t run_waiting = 0;
  bool run_joined = false;
  const std::size_t n = candidates.size();
  for (std::size_t i = 0; i < n; ++i) {
    const PublishedCell& c = candidates[i];
    prefetchAhead(candidates, i);
    const CellKey slab = PublishedBlock::blockKeyOf(c.key);
    if (!in_run || !(slab == run_slab)) {
      in_run = true;
      run_slab = slab;
      run_waiting = waiting ? deferred_.waitingIn(slab) : 0;
      run_joined = false;
    }
    if ((run_waiting >> PublishedBlock::localIndexOf(c.key) & 1U) != 0) {
      deferred_.refresh(c, judge(c, step, variance_step).first);
      run_waiting = deferred_.waitingIn(slab);  // the cell may have left
      continue;
    }
    if (!run_joined) {
      if (judge(c, step, variance_step).first == Worth::kNothing) continue;
      stale_.markCellsSlab(c.key);
      run_joined = true;
    }
    ++overflowed_;
  }
}

void DeltaStream::takeDeferred(Worth worth, std::size_t& room) {
  const std::int32_t step = rule_.quantisedStep();
  const double variance_step = rule_.variance_step;
  std::vector<DeferredCells::Entry> taken;
  while (room > 0 && deferred_.take(worth, room, taken) > 0) {
    for (const DeferredCells::Entry& e : taken) {
      bool send = false;
      map_.setIf(e.cell, [&](const PublishedCell& published, bool present) {
        send = !(e.was_published && !present) && worthSending(e.cell, published, step, variance_step) != Worth::kNothing;
        return false;
      });
      if (!send) continue;
      chosen_.push_back(e);
      --room;
    }
    taken.clear();
  }
}

void DeltaStream::wait(const DeferredCells::Entry& entry) {
  if (deferred_.add(entry)) return;
  ++overflowed_;
  if (entry.worth == Worth::kClass) {
    // A class change is worth more to a client than a probability move: the oldest waiting move leaves.
    evicted_.clear();
    if (deferred_.take(Worth::kProbability, 1, evicted_) == 1) {
      stale_.markCellsSlab(evicted_.front().cell.key);
      deferred_.add(entry);
      return;
    }
  }
  stale_.markCellsSlab(entry.cell.key);
}

std::vector<CellKey> DeltaStream::staleSlabsToRead(std::size_t max) {
  std::vector<CellKey> slabs;
  stale_.take(std::min(max, deferred_.room() / PublishedBlock::kCells), slabs);
  return slabs;
}

void DeltaStream::refreshStale(std::span<const PublishedCell> cells) {
  const std::int32_t step = rule_.quantisedStep();
  const double variance_step = rule_.variance_step;
  for (const PublishedCell& c : cells) {
    const auto [worth, present] = judge(c, step, variance_step);
    if (deferred_.refresh(c, worth)) continue;
    if (worth != Worth::kNothing) wait({c, worth, present});
  }
}

std::int64_t DeltaStream::partBytes(std::size_t cells) {
  static const std::int64_t header = ogf::map_delta_t{}.getEncodedSize();
  // key_x, key_y, key_z, probability, cell_class, variance.
  constexpr std::int64_t kCellBytes = 3 * 4 + 2 + 1 + 4;
  return header + kCellBytes * static_cast<std::int64_t>(cells);
}

std::int64_t DeltaStream::bytesOf(std::span<const ogf::map_delta_t> messages) {
  std::int64_t bytes = 0;
  for (const auto& m : messages) bytes += partBytes(static_cast<std::size_t>(m.num_cells));
  return bytes;
}

void DeltaStream::limitWaitingTo(double bytes_per_s, double seconds) {
  const double bytes = std::min(bytes_per_s * seconds, 1e15);  // within int64 whatever the configuration
  limitWaiting(cellsWithin(static_cast<std::int64_t>(bytes)));
}

std::size_t DeltaStream::cellsWithin(std::int64_t bytes) const {
  const auto per = static_cast<std::size_t>(config_.max_cells_per_message);
  const std::int64_t full = partBytes(per);
  const std::int64_t header = partBytes(0);
  const std::int64_t cell = partBytes(1) - header;
  if (bytes <= 0) return 0;
  const auto parts = static_cast<std::size_t>(bytes / full);
  const std::int64_t rest = bytes - static_cast<std::int64_t>(parts) * full;
  const std::size_t extra = rest > header ? std::min<std::size_t>(per, static_cast<std::size_t>((rest - header) / cell)) : 0;
  return parts * per + extra;
}

std::vector<ogf::map_delta_t> DeltaStream::keyframe(std::int64_t utime) const {
  return split(utime, ogf::map_delta_t::KIND_KEYFRAME, -1, map_.sortedCells());
}

void DeltaStream::reset(std::span<const PublishedCell> cells, std::int64_t seq) {
  seq_ = seq;
  map_.clear();
  deferred_.clear();
  stale_.clear();
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
