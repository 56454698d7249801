// The banded OGF: batch ordering, block allocation, the coloured parallel sweep and the rank-1 update of
// eq. (5) restricted to the stencil.
#include "ogf/filter/banded_ogf.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "ogf/filter/layer_changes.hpp"
#include "ogf/filter/map_checksum.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/filter/probit_update.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

namespace {

std::uint32_t colourOf(const CellKey& blockKey) {
  return static_cast<std::uint32_t>((blockKey.x & 1) | ((blockKey.y & 1) << 1) | ((blockKey.z & 1) << 2));
}

// Block d of the 3×3×3 neighbourhood of `block`, d = (dx+1) + 3(dy+1) + 9(dz+1).
CellKey neighbourOf(const CellKey& block, unsigned d) {
  return block + CellKey{static_cast<int>(d % 3) - 1, static_cast<int>((d / 3) % 3) - 1, static_cast<int>(d / 9) - 1};
}

// Sorts a group's codes (position << 1 | y, below 1024): through a 1024-bit set when they are distinct (one
// measurement per cell, as a scan's are), by std::sort when one repeats.
void sortCodes(std::span<std::uint16_t> codes) {
  std::array<std::uint64_t, 16> present{};
  for (const std::uint16_t c : codes) {
    std::uint64_t& word = present[c >> 6];
    const std::uint64_t bit = std::uint64_t{1} << (c & 63U);
    if ((word & bit) != 0) {
      std::sort(codes.begin(), codes.end());
      return;
    }
    word |= bit;
  }
  std::size_t i = 0;
  for (std::size_t w = 0; w < present.size(); ++w) {
    for (std::uint64_t rest = present[w]; rest != 0; rest &= rest - 1) {
      codes[i++] = static_cast<std::uint16_t>(w * 64 + static_cast<std::size_t>(std::countr_zero(rest)));
    }
  }
}

// Calls visit(l) for every set bit l of a 512-bit set, in increasing order.
template <class Visit>
void forEachBit(const std::array<std::uint64_t, 8>& bits, Visit&& visit) {
  for (std::size_t w = 0; w < bits.size(); ++w) {
    for (std::uint64_t rest = bits[w]; rest != 0; rest &= rest - 1) {
      visit(w * 64 + static_cast<std::size_t>(std::countr_zero(rest)));
    }
  }
}

// Bits of each 8-bit row with x in [from, 8), replicated over the 8 rows of a layer.
constexpr std::uint64_t rowsFrom(int from) { return (0xFFULL << from & 0xFFULL) * 0x0101010101010101ULL; }

// A z layer of a block's cells (bit x + 8y) dilated along x by the offsets of `dxs` (bit dx + 8 per dx,
// |dx| ≤ 8, a 2-D stencil's reach): the parts in the block before (index 0), in the block itself (1) and in
// the block after (2).
std::array<std::uint64_t, 3> dilatedAlongX(std::uint64_t w, std::uint32_t dxs) {
  std::array<std::uint64_t, 3> parts{};
  for (std::uint32_t rest = dxs; rest != 0; rest &= rest - 1) {
    const int dx = std::countr_zero(rest) - 8;
    if (dx >= 0) {
      parts[1] |= (w << dx) & rowsFrom(dx);
      parts[2] |= dx == 0 ? 0 : (w >> (8 - dx)) & ~rowsFrom(dx);
    } else {
      parts[1] |= (w >> -dx) & ~rowsFrom(8 + dx);
      parts[0] |= (w << (8 + dx)) & rowsFrom(8 + dx);
    }
  }
  return parts;
}

}  // namespace

// The measurements of a batch in one block.
struct BandedOgf::Group {
  CellKey block;
  std::uint32_t colour = 0;
  std::uint32_t neighbours = 0;  // bit d set: block d of the 3×3×3 neighbourhood is touched
  std::size_t begin = 0;         // range in the sorted measurement keys
  std::size_t end = 0;
  std::uint8_t* marks = nullptr;  // the block's cell marks when it existed before the batch (occupied priority)
  const float* data = nullptr;    // the block's values when it existed before the batch (dropClampedFree)
};

Result<BandedOgf> BandedOgf::create(const FilterConfig& config) {
  auto resolved = config.resolved();
  if (!resolved) {
    return resolved.error();
  }
  return BandedOgf(*resolved);
}

BandedOgf::BandedOgf(const FilterConfig& resolved)
    : config_(resolved),
      prior_(resolved.prior()),
      stencil_(resolved.dimensions, resolved.stencilShape()),
      storage_(resolved.dimensions, floatsPerBlockOf(resolved.dimensions, resolved.covariance, stencil_)),
      published_(resolved.occupiedThreshold, resolved.freeThreshold),
      band_(stencil_, resolved.dimensions, resolved.covariance),
      locate_(resolved.covariance == CovarianceStorage::kBanded ? bandLocateFor(band_) : &compactBandLocate),
      kernel_(resolved.covariance == CovarianceStorage::kBanded ? bandKernelFor(band_)
                                                                : compactBandKernelFor(band_)),
      layerChanges_(layerChangesFor(cpuHasFma())) {
  if (resolved.covariance == CovarianceStorage::kBanded) {
    for (const CellKey& o : stencil_.forwardOffsets()) {
      priorSlots_.push_back(static_cast<float>(prior_(o)));
    }
  } else {
    for (const CellKey& o : stencil_.offsets()) {
      band_.correlation.push_back(static_cast<float>(prior_(o)));
    }
    band_.priorVariance = static_cast<float>(prior_.variance());
  }
  priorVariance_ = static_cast<float>(prior_.variance());
  varianceFloor_ = priorVariance_ * 1e-9F;
  if (compact()) {
    inverseScales_.resize(std::size_t{1} << 16);
    for (std::size_t c = 0; c < inverseScales_.size(); ++c) {
      const double var =
          static_cast<double>(priorVariance_ * decodeVarianceRatio(static_cast<std::uint16_t>(c)));
      inverseScales_[c] = 1.0 / std::sqrt(1.0 + var);
    }
  }
  dropsClampedFree_ = compact() && std::ranges::all_of(band_.correlation, [](float c) { return c >= 0.0F; });
  derivePolicyState();
  // Same-colour blocks are one block apart: their measurements touch disjoint cells iff 2·extent ≤ B.
  parallelSafe_ = 2 * stencil_.extent() <= kBlockSide;
  // The stencil by rows along x: per (dy, dz), the set of its dx (bit dx + 8), and the distinct sets.
  for (const CellKey& o : stencil_.offsets()) {
    const std::uint32_t bit = 1U << static_cast<unsigned>(o.x + 8);
    const auto it = std::ranges::find_if(
        stencilRows_, [&](const StencilRow& row) { return row.dy == o.y && row.dz == o.z; });
    if (it == stencilRows_.end()) {
      stencilRows_.push_back({o.y, o.z, bit});
    } else {
      it->set |= bit;  // the set itself until every offset is in
    }
  }
  for (StencilRow& row : stencilRows_) {
    const std::uint32_t dxs = row.set;
    auto it = std::ranges::find(stencilRowSets_, dxs);
    if (it == stencilRowSets_.end()) {
      stencilRowSets_.push_back(dxs);
      it = stencilRowSets_.end() - 1;
    }
    row.set = static_cast<std::uint32_t>(it - stencilRowSets_.begin());
  }
  // Which neighbouring blocks a measurement at each local position reaches.
  const int e = stencil_.extent();
  const bool flat = config_.dimensions == 2;
  neighbourMask_.resize(storage_.cellsPerBlock());
  for (std::size_t l = 0; l < neighbourMask_.size(); ++l) {
    const int local[3] = {static_cast<int>(l & 7U), static_cast<int>((l >> 3) & 7U), static_cast<int>(l >> 6)};
    int lo[3];
    int hi[3];
    for (int a = 0; a < 3; ++a) {
      const int reach = (a == 2 && flat) ? 0 : e;
      lo[a] = (local[a] - reach) >> 3;
      hi[a] = (local[a] + reach) >> 3;
    }
    std::uint32_t mask = 0;
    for (int dz = lo[2]; dz <= hi[2]; ++dz) {
      for (int dy = lo[1]; dy <= hi[1]; ++dy) {
        for (int dx = lo[0]; dx <= hi[0]; ++dx) {
          mask |= 1U << static_cast<unsigned>((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1));
        }
      }
    }
    neighbourMask_[l] = mask;
  }
}

std::size_t BandedOgf::floatsPerBlockOf(int dimensions, CovarianceStorage storage, const Stencil& stencil) {
  const std::size_t cells = dimensions == 3 ? 512 : 64;
  // Compact: a float mean and a 16-bit variance code per cell.
  return storage == CovarianceStorage::kCompact ? cells + cells / 2 : cells * (2 + stencil.forwardOffsets().size());
}

void BandedOgf::initialiseBlock(Block& block) {
  block.clearMarks();
  if (compact()) {
    const std::size_t cells = block.cells();
    std::fill_n(block.data(), cells, 0.0F);
    std::fill_n(reinterpret_cast<std::uint16_t*>(block.data() + cells), cells, encodeVarianceRatio(1.0F));
    return;
  }
  // The prior record in the first cell, then copied over the block in doubling steps.
  float* d = block.data();
  d[0] = 0.0F;
  d[1] = priorVariance_;
  std::copy(priorSlots_.begin(), priorSlots_.end(), d + 2);
  const std::size_t total = block.values().size();
  for (std::size_t done = floatsPerCell(); done < total; done *= 2) {
    std::memcpy(d + done, d, std::min(done, total - done) * sizeof(float));
  }
}

WorkerPool* BandedOgf::pool() {
  if (config_.threads <= 1) {
    return nullptr;
  }
  if (pool_ == nullptr || pool_->threads() != static_cast<std::size_t>(config_.threads)) {
    pool_ = std::make_unique<WorkerPool>(config_.threads);
  }
  return pool_.get();
}

template <class Body>
void BandedOgf::shareOut(std::size_t n, bool worthSharing, Body&& body) {
  WorkerPool* threads = worthSharing ? pool() : nullptr;
  if (threads == nullptr) {
    body(std::size_t{0}, n);
    return;
  }
  const EvenSplit split{n, threads->threads()};
  threads->run([&](std::size_t p) { body(split.begin(p), split.begin(p + 1)); });
}

std::uint32_t BandedOgf::lookUp(const CellKey& blockKey) {
  Batch& work = scratch_;
  bool inserted = false;
  const auto next = static_cast<std::uint32_t>(work.touched.size());
  const std::uint32_t t = work.touchedIndex.findOrInsert(blockKey, next, inserted);
  if (inserted) {
    work.touched.push_back({blockKey, storage_.find(blockKey), {}});
  }
  return t;
}

void BandedOgf::initialiseBlocks(std::span<Block* const> blocks) {
  const auto initialise = [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) {
      initialiseBlock(*blocks[b]);
    }
  };
  // In allocation order, so each thread writes its own run of the arena's pages.
  shareOut(blocks.size(), blocks.size() >= kParallelBlocksMin, initialise);
}

inline bool BandedOgf::holdBackFree(std::uint8_t& mark) const {
  if ((mark & CellMark::kHit) == 0) {
    return false;
  }
  const int count = (mark & CellMark::kCount) + 1;
  if (config_.freeReleaseCount == 0 || count < config_.freeReleaseCount) {
    mark = static_cast<std::uint8_t>(CellMark::kHit | std::min(count, static_cast<int>(CellMark::kCount)));
    return true;
  }
  mark = 0;  // released: free measurements apply again until the next occupied one
  return false;
}

// The stages of a batch, in order; the change detection (recordChangeableCells, reportChanges) only with a
// sink.
UpdateStats BandedOgf::update(std::span<const Measurement> batch, ChangeSink* sink) {
  UpdateStats stats;
  std::vector<Group> groups = groupByBlock(batch, stats);
  if (dropsClampedFree_ && skipsClampedEarly_ && std::isfinite(freeClampZ_)) {
    dropClampedFree(groups, stats);
  }
  const std::vector<Group> sorted = orderGroups(groups);
  obtainNeighbourhoods(sorted, stats);
  scratch_.touchedOrder.clear();
  if (sink != nullptr) {
    recordChangeableCells(sorted);
  }
  applyColours(sorted, stats);
  if (sink != nullptr) {
    reportChanges(*sink);
  }
  return stats;
}

// Runs of consecutive measurements in one block (a scan's come block by block), each run's block looked up
// once: where each starts, then the batch's end.
inline void BandedOgf::findRuns(std::span<const Measurement> batch) {
  std::vector<std::size_t>& runs = scratch_.runs;
  runs.clear();
  for (std::size_t i = 0; i < batch.size(); ++i) {
    if (i == 0 || !(blockKeyOf(batch[i].key) == blockKeyOf(batch[i - 1].key))) {
      runs.push_back(i);
    }
  }
  runs.push_back(batch.size());
}

// The blocks of the runs ahead of run r asked of the CPU in stages, the table's slot, then the block's
// header, then its marks: a scan reaches thousands of blocks, far more than the cache holds.
inline void BandedOgf::prefetchRunsAhead(std::span<const Measurement> batch, std::size_t r,
                                         std::array<const Block*, kRunHeaderAhead>& foundAhead) const {
  const std::vector<std::size_t>& runs = scratch_.runs;
  const std::size_t runCount = runs.size() - 1;
  const auto runBlock = [&](std::size_t q) { return blockKeyOf(batch[runs[q]].key); };
  if (r + kRunSlotAhead < runCount) {
    storage_.prefetch(runBlock(r + kRunSlotAhead));
  }
  if (r + kRunHeaderAhead < runCount) {
    const Block* b = storage_.find(runBlock(r + kRunHeaderAhead));
    foundAhead[(r + kRunHeaderAhead) % kRunHeaderAhead] = b;
    if (b != nullptr) {
      __builtin_prefetch(b, 1);
    }
  }
  if (prioritisesOccupied() && r + kRunMarksAhead < runCount) {
    // Found kRunHeaderAhead − kRunMarksAhead runs ago (null for the first runs, which had no stage).
    if (const Block* b = foundAhead[(r + kRunMarksAhead) % kRunHeaderAhead]; b != nullptr) {
      const std::span<const std::uint8_t> marks = b->marks();
      for (std::size_t line = 0; line < marks.size(); line += 64) {
        __builtin_prefetch(marks.data() + line, 1);
      }
    }
  }
}

// Whether a measurement can be applied at all: y is ±1, and in a 2-D map it lies on the z = 0 slice.
inline bool BandedOgf::acceptable(const Measurement& m) const {
  return (m.y == 1 || m.y == -1) && (config_.dimensions != 2 || m.key.z == 0);
}

// The measurements [i, end) of one run into `group` (number g) from `next` on: rejected ones counted,
// free ones held back (marks: the block's, when it existed and the occupied priority holds), each other
// one's group and code (position in the block, y), and the neighbouring blocks they reach and their count
// (Group::end for now).
inline void BandedOgf::acceptRun(std::span<const Measurement> batch, std::size_t i, std::size_t end,
                                 std::uint32_t g, Group& group, std::size_t& next, UpdateStats& stats) {
  Batch& work = scratch_;
  std::uint8_t* marks = group.marks;
  std::size_t out = next;  // in a register through the loop, not through the reference
  std::uint32_t neighbours = 0;
  std::size_t count = 0;
  for (; i < end; ++i) {
    const Measurement& m = batch[i];
    if (!acceptable(m)) {
      ++stats.rejected;
      continue;
    }
    const std::size_t local = localIndexOf(m.key);
    // A cell's marks before the batch decide (occupied measurements mark it in obtainNeighbourhoods), so the
    // outcome does not depend on the order of the batch.
    if (m.y < 0 && marks != nullptr && holdBackFree(marks[local])) {
      ++stats.heldBack;
      continue;
    }
    neighbours |= neighbourMask_[local];
    ++count;
    work.groupOf[out] = g;
    work.codes[out] = static_cast<std::uint16_t>((local << 1) | (m.y > 0 ? 1U : 0U));
    ++out;
  }
  next = out;
  group.neighbours |= neighbours;
  group.end += count;
}

// The group of a block the batch measures, with the block's marks (when the occupied priority holds:
// it is then written, and its hash forgotten) and values, where it existed before the batch.
BandedOgf::Group BandedOgf::makeGroup(const CellKey& block, Block* existing) const {
  std::uint8_t* existingMarks = nullptr;
  if (existing != nullptr && prioritisesOccupied()) {
    existing->changed();  // holding back free measurements counts on the marks
    existingMarks = existing->marks().data();
  }
  return {block, colourOf(block), 0, 0, 0, existingMarks, existing != nullptr ? existing->data() : nullptr};
}

// The measurements of run r: its group (made at its first acceptable measurement, or found when the block
// came in an earlier run), then acceptRun.
inline void BandedOgf::groupRun(std::span<const Measurement> batch, std::size_t r, std::vector<Group>& groups,
                                std::size_t& accepted, UpdateStats& stats) {
  Batch& work = scratch_;
  std::size_t i = work.runs[r];
  const std::size_t end = work.runs[r + 1];
  for (; i < end && !acceptable(batch[i]); ++i) {
    ++stats.rejected;
  }
  if (i == end) {
    return;
  }
  const CellKey block = blockKeyOf(batch[i].key);
  bool inserted = false;
  const std::uint32_t g = work.blocks.findOrInsert(block, static_cast<std::uint32_t>(groups.size()), inserted);
  if (inserted) {
    groups.push_back(makeGroup(block, readsBlocks() ? work.touched[lookUp(block)].block : nullptr));
  } else {
    work.groupsInRuns = false;
  }
  acceptRun(batch, i, end, g, groups[g], accepted, stats);
}

// 1. The blocks of the batch (a group each), and per measurement its group and a code (position in the
//    block, y); measurements that are not ±1 (or off the 2-D slice) rejected, free ones held back.
std::vector<BandedOgf::Group> BandedOgf::groupByBlock(std::span<const Measurement> batch,
                                                      UpdateStats& stats) {
  Batch& work = scratch_;
  work.groupOf.resize(batch.size());
  work.codes.resize(batch.size());
  std::vector<Group> groups;
  if (WorkerPool* threads = batch.size() >= kParallelBatchMin ? pool() : nullptr; threads != nullptr) {
    if (groupInParallel(batch, groups, stats, *threads)) {
      return groups;
    }
    groups.clear();
  }
  work.blocks.clear();
  work.touchedIndex.clear();
  work.touched.clear();
  work.groupsInRuns = true;
  findRuns(batch);
  const std::size_t runCount = work.runs.size() - 1;
  // Only for batches in runs (a scan's): in a batch in no order of blocks, a run is a measurement, and
  // the look-ups ahead would double those the measurements make themselves.
  const bool prefetchRuns = readsBlocks() && runCount * kMinRunForPrefetch <= batch.size();
  // The blocks found at the header stage, by run mod kRunHeaderAhead, for the marks stage to reuse.
  std::array<const Block*, kRunHeaderAhead> foundAhead{};
  std::size_t accepted = 0;
  for (std::size_t r = 0; r < runCount; ++r) {
    if (prefetchRuns) {
      prefetchRunsAhead(batch, r, foundAhead);
    }
    groupRun(batch, r, groups, accepted, stats);
  }
  work.groupOf.resize(accepted);
  work.codes.resize(accepted);
  return groups;
}

// groupByBlock on the pool's threads, for a batch whose blocks come in one run each (a scan's). Three
// passes: the threads find the runs of their shares of the batch and look their blocks up in the map; one
// thread numbers the groups in the order of the runs (as groupRun does); the threads accept the
// measurements of their shares of the runs (acceptRun), each into its own part of the arrays, and these
// are closed up in order. The result is groupByBlock's on one thread. False (nothing kept) for a batch
// in which a block comes in two runs, or whose runs are single measurements.
bool BandedOgf::groupInParallel(std::span<const Measurement> batch, std::vector<Group>& groups,
                                UpdateStats& stats, WorkerPool& threads) {
  Batch& work = scratch_;
  const std::size_t n = batch.size();
  const EvenSplit split{n, threads.threads()};
  std::vector<RunPart>& parts = work.runParts;
  parts.resize(split.parts);
  const bool readsExisting = readsBlocks();
  const auto runBlock = [&](std::size_t i) { return blockKeyOf(batch[i].key); };
  threads.run([&](std::size_t p) {
    RunPart& part = parts[p];
    part.starts.clear();
    part.blocks.clear();
    part.acceptable.clear();
    const std::size_t b = split.begin(p);
    const std::size_t e = split.begin(p + 1);
    for (std::size_t i = b; i < e; ++i) {
      if (i == 0 || !(runBlock(i) == runBlock(i - 1))) {
        part.starts.push_back(i);
      }
    }
    std::size_t last = e;  // where the part's last run ends: in the next part, or at the batch's end
    while (last < n && runBlock(last) == runBlock(last - 1)) {
      ++last;
    }
    for (std::size_t j = 0; j < part.starts.size(); ++j) {
      const std::size_t runEnd = j + 1 < part.starts.size() ? part.starts[j + 1] : last;
      bool any = false;
      for (std::size_t i = part.starts[j]; i < runEnd && !any; ++i) {
        any = acceptable(batch[i]);
      }
      part.acceptable.push_back(any ? 1 : 0);
      if (readsExisting && j + kRunSlotAhead < part.starts.size()) {
        storage_.prefetch(runBlock(part.starts[j + kRunSlotAhead]));
      }
      part.blocks.push_back(readsExisting && any ? storage_.find(runBlock(part.starts[j])) : nullptr);
    }
  });
  std::vector<std::size_t>& runs = work.runs;
  runs.clear();
  std::vector<Block*>& blocksOfRuns = work.runBlocks;
  blocksOfRuns.clear();
  std::vector<std::uint8_t>& acceptableRuns = work.runAcceptable;
  acceptableRuns.clear();
  for (const RunPart& part : parts) {
    runs.insert(runs.end(), part.starts.begin(), part.starts.end());
    blocksOfRuns.insert(blocksOfRuns.end(), part.blocks.begin(), part.blocks.end());
    acceptableRuns.insert(acceptableRuns.end(), part.acceptable.begin(), part.acceptable.end());
  }
  runs.push_back(n);
  const std::size_t runCount = runs.size() - 1;
  if (runCount * kMinRunForPrefetch > n) {
    return false;
  }
  // The groups, numbered in the order of their runs, and the blocks looked up, as groupRun makes them.
  work.blocks.clear();
  work.touchedIndex.clear();
  work.touched.clear();
  std::vector<std::uint32_t>& groupOfRun = work.runGroups;
  groupOfRun.assign(runCount, BlockKeyTable::kAbsent);
  for (std::size_t r = 0; r < runCount; ++r) {
    if (acceptableRuns[r] == 0) {
      continue;
    }
    const CellKey block = runBlock(runs[r]);
    bool inserted = false;
    const auto g = work.blocks.findOrInsert(block, static_cast<std::uint32_t>(groups.size()), inserted);
    if (!inserted) {
      return false;  // the block's measurements in two runs: one thread takes them in order
    }
    if (readsExisting) {
      work.touchedIndex.findOrInsert(block, static_cast<std::uint32_t>(work.touched.size()), inserted);
      if (inserted) {
        work.touched.push_back({block, blocksOfRuns[r], {}});
      }
    }
    groups.push_back({block, colourOf(block), 0, 0, 0, nullptr, nullptr});
    groupOfRun[r] = g;
  }
  // The runs shared out by measurements; each thread's accepted measurements start where its runs do.
  const auto firstRunFrom = [&](std::size_t i) {
    return static_cast<std::size_t>(std::lower_bound(runs.begin(), runs.end() - 1, i) - runs.begin());
  };
  threads.run([&](std::size_t p) {
    RunPart& part = parts[p];
    part.counts = {};
    const std::size_t r0 = firstRunFrom(split.begin(p));
    const std::size_t r1 = p + 1 == split.parts ? runCount : firstRunFrom(split.begin(p + 1));
    part.from = runs[r0];
    std::size_t next = part.from;
    for (std::size_t r = r0; r < r1; ++r) {
      if (prioritisesOccupied() && r + kRunMarksAhead < r1) {
        if (const Block* ahead = blocksOfRuns[r + kRunMarksAhead]; ahead != nullptr) {
          for (std::size_t line = 0; line < ahead->marks().size(); line += 64) {
            __builtin_prefetch(ahead->marks().data() + line, 1);
          }
        }
      }
      const std::uint32_t g = groupOfRun[r];
      if (g == BlockKeyTable::kAbsent) {
        part.counts.rejected += runs[r + 1] - runs[r];
        continue;
      }
      Group& group = groups[g];
      group = makeGroup(group.block, blocksOfRuns[r]);
      acceptRun(batch, runs[r], runs[r + 1], g, group, next, part.counts);
    }
    part.kept = next - part.from;
  });
  std::size_t accepted = 0;
  for (const RunPart& part : parts) {
    closeUp(part.from, part.kept, accepted);
    accepted += part.kept;
    stats.rejected += part.counts.rejected;
    stats.heldBack += part.counts.heldBack;
  }
  work.groupOf.resize(accepted);
  work.codes.resize(accepted);
  work.groupsInRuns = true;
  return true;
}

// Moves `count` measurements (their codes and groups) from `from` down to `to` (≤ from), where a thread's
// share of a stage left them, so the shares follow one another.
void BandedOgf::closeUp(std::size_t from, std::size_t count, std::size_t to) {
  Batch& work = scratch_;
  if (from == to) {
    return;
  }
  std::copy_n(work.codes.begin() + static_cast<std::ptrdiff_t>(from), count,
              work.codes.begin() + static_cast<std::ptrdiff_t>(to));
  std::copy_n(work.groupOf.begin() + static_cast<std::ptrdiff_t>(from), count,
              work.groupOf.begin() + static_cast<std::ptrdiff_t>(to));
}

// 2. The deterministic order: colour, block key, position in the block (then y). Groups are sorted (by
//    colour alone, stably, when they came in key order, as a scan's do), the measurements placed by group,
//    then each group's few codes sorted.
std::vector<BandedOgf::Group> BandedOgf::orderGroups(std::vector<Group>& groups) {
  Batch& work = scratch_;
  std::vector<std::uint32_t> order(groups.size());
  bool keyOrder = true;
  for (std::size_t g = 1; g < groups.size() && keyOrder; ++g) {
    keyOrder = groups[g - 1].block < groups[g].block;
  }
  if (keyOrder) {
    std::array<std::size_t, 9> first{};  // where each colour starts in `order`
    for (const Group& g : groups) {
      ++first[g.colour + 1];
    }
    for (std::size_t c = 1; c < first.size(); ++c) {
      first[c] += first[c - 1];
    }
    for (std::uint32_t g = 0; g < groups.size(); ++g) {
      order[first[groups[g].colour]++] = g;
    }
  } else {
    for (std::uint32_t g = 0; g < order.size(); ++g) {
      order[g] = g;
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return groups[a].colour != groups[b].colour ? groups[a].colour < groups[b].colour
                                                  : groups[a].block < groups[b].block;
    });
  }
  std::vector<Group> sorted(groups.size());
  std::size_t placed = 0;
  for (std::uint32_t r = 0; r < order.size(); ++r) {
    Group& g = groups[order[r]];
    const std::size_t count = g.end;
    g.begin = placed;
    g.end = placed + count;
    placed += count;
    sorted[r] = g;
  }
  work.sorted.resize(placed);
  const auto sortGroupCodes = [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      sortCodes(std::span<std::uint16_t>(work.sorted).subspan(sorted[r].begin, sorted[r].end - sorted[r].begin));
    }
  };
  if (!work.groupsInRuns) {
    // Scattered: each measurement to its group's cursor, in the order of the batch.
    std::vector<std::size_t> cursor(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) {
      cursor[g] = groups[g].begin;
    }
    for (std::size_t i = 0; i < work.codes.size(); ++i) {
      work.sorted[cursor[work.groupOf[i]]++] = work.codes[i];
    }
    sortGroupCodes(0, sorted.size());
    return sorted;
  }
  // Each group's measurements are consecutive, groups in the order they were made: copied a group at a
  // time, the threads taking shares of the groups where there are enough measurements.
  std::vector<std::size_t>& from = work.groupFrom;
  from.resize(groups.size());
  std::size_t source = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    from[g] = source;
    source += groups[g].end - groups[g].begin;
  }
  const auto placeGroups = [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      std::copy_n(work.codes.begin() + static_cast<std::ptrdiff_t>(from[order[r]]), sorted[r].end - sorted[r].begin,
                  work.sorted.begin() + static_cast<std::ptrdiff_t>(sorted[r].begin));
    }
    sortGroupCodes(r0, r1);
  };
  shareOut(sorted.size(), placed >= kParallelBatchMin, placeGroups);
  return sorted;
}

// 3. Every block the batch touches, allocated up front (serially, in order; the new ones then initialised
//    on all threads); each group's neighbourhood of block data kept for applyColours, the blocks' numbers
//    for recordChangeableCells, and the occupied measurements marked (OccupiedPriority::kMap).
void BandedOgf::obtainNeighbourhoods(std::span<const Group> sorted, UpdateStats& stats) {
  Batch& work = scratch_;
  work.neighbourhoods.assign(sorted.size() * 27, nullptr);
  work.groupTouched.resize(sorted.size() * 27);
  work.freshBlocks.clear();
  work.freshOwnGroups.clear();
  try {
    findNeighbourhoods(sorted);
  } catch (...) {
    initialiseBlocks(work.freshBlocks);  // none left unwritten in the map
    throw;
  }
  initialiseBlocks(work.freshBlocks);
  stats.blocksAllocated += work.freshBlocks.size();
  for (const std::uint32_t r : work.freshOwnGroups) {
    markOccupied(*work.touched[work.groupTouched[r * 27 + kOwnBlock]].block, codesOf(sorted[r]));
  }
}

std::span<const std::uint16_t> BandedOgf::codesOf(const Group& g) const {
  return std::span<const std::uint16_t>(scratch_.sorted).subspan(g.begin, g.end - g.begin);
}

// obtainNeighbourhoods' pass over the groups: their blocks looked up, or allocated unwritten (listed in
// Batch::freshBlocks), and the occupied measurements of the groups whose block is not new marked.
void BandedOgf::findNeighbourhoods(std::span<const Group> sorted) {
  Batch& work = scratch_;
  // The neighbourhoods ahead: the table slots of their blocks asked of the CPU kGroupSlotAhead groups
  // early, the blocks looked up (and numbered) kGroupLookAhead groups early and their headers asked for,
  // as each is marked written below. A scan's blocks are far more than the cache holds.
  const auto prefetchSlots = [&](const Group& g) {
    for (std::uint32_t rest = g.neighbours; rest != 0; rest &= rest - 1) {
      storage_.prefetch(neighbourOf(g.block, static_cast<unsigned>(std::countr_zero(rest))));
    }
  };
  const auto lookUpNeighbourhood = [&](std::size_t q) {
    const Group& g = sorted[q];
    for (std::uint32_t rest = g.neighbours; rest != 0; rest &= rest - 1) {
      const auto d = static_cast<unsigned>(std::countr_zero(rest));
      const std::uint32_t t = lookUp(neighbourOf(g.block, d));
      work.groupTouched[q * 27 + d] = t;
      const TouchedBlock& ahead = work.touched[t];
      if (ahead.block != nullptr && !ahead.written) {
        __builtin_prefetch(ahead.block, 1);
      }
    }
  };
  for (std::size_t q = 0; q < std::min(kGroupSlotAhead, sorted.size()); ++q) {
    prefetchSlots(sorted[q]);
  }
  for (std::size_t q = 0; q < std::min(kGroupLookAhead, sorted.size()); ++q) {
    lookUpNeighbourhood(q);
  }
  const bool occupiedPriority = prioritisesOccupied();
  for (std::size_t r = 0; r < sorted.size(); ++r) {
    if (r + kGroupSlotAhead < sorted.size()) {
      prefetchSlots(sorted[r + kGroupSlotAhead]);
    }
    if (r + kGroupLookAhead < sorted.size()) {
      lookUpNeighbourhood(r + kGroupLookAhead);
    }
    const Group& g = sorted[r];
    for (unsigned d = 0; d < 27; ++d) {
      if ((g.neighbours >> d) & 1U) {
        const CellKey key = neighbourOf(g.block, d);
        const std::uint32_t t = work.groupTouched[r * 27 + d];
        TouchedBlock& touched = work.touched[t];
        if (!touched.written) {
          if (touched.block == nullptr) {
            touched.block = &storage_.obtainUnwritten(key, touched.fresh);
            if (touched.fresh) {
              work.freshBlocks.push_back(touched.block);
            }
          } else {
            touched.block->changed();  // about to be written (as BlockStorage::obtain marks it)
          }
          touched.written = true;
        }
        Block& block = *touched.block;
        work.neighbourhoods[r * 27 + d] = block.data();
        if (d == kOwnBlock && occupiedPriority) {
          if (touched.fresh) {
            work.freshOwnGroups.push_back(static_cast<std::uint32_t>(r));
          } else {
            markOccupied(block, codesOf(g));
          }
        }
      }
    }
  }
}

// 4. With a sink: the cells the updates can change (the stencils of the measurements), and their mean and
//    variance before, to find what changed. Blocks in key order, cells in position order.
void BandedOgf::recordChangeableCells(std::span<const Group> sorted) {
  Batch& work = scratch_;
  // Per neighbour (of the 3×3×3 blocks) and z layer, the group's cells the stencil reaches; kept zero
  // between groups.
  std::array<std::array<std::uint64_t, 8>, 27> reached{};
  for (std::size_t r = 0; r < sorted.size(); ++r) {
    markStencilReach(sorted[r], &work.groupTouched[r * 27], reached);
  }
  std::vector<std::uint32_t>& touchedOrder = work.touchedOrder;
  touchedOrder.resize(work.touched.size());
  for (std::uint32_t t = 0; t < touchedOrder.size(); ++t) {
    touchedOrder[t] = t;
  }
  std::sort(touchedOrder.begin(), touchedOrder.end(),
            [&](std::uint32_t a, std::uint32_t b) { return work.touched[a].key < work.touched[b].key; });
  if (compact()) {
    copyTouchedLayers(work);
  } else {
    copyTouchedCells(work);
  }
}

// The cells the stencils of group g's measurements reach, added to the TouchedBlock::cells of its
// neighbourhood (`touchedOfGroup`: the touched block number of each of its 27 neighbours); `reached` is
// zero before and after.
void BandedOgf::markStencilReach(const Group& g, const std::uint32_t* touchedOfGroup,
                                 std::array<std::array<std::uint64_t, 8>, 27>& reached) {
  Batch& work = scratch_;
  std::vector<std::array<std::uint64_t, 3>>& alongX = work.alongX;
  // The group's measured positions, dilated by the stencil a row of it at a time: along x once per set of
  // dx (dilatedAlongX), then shifted by the row's dy and dz as whole 8-bit rows and layers.
  std::array<std::uint64_t, 8> measured{};
  for (std::size_t i = g.begin; i < g.end; ++i) {
    const std::size_t l = work.sorted[i] >> 1;
    measured[l >> 6] |= std::uint64_t{1} << (l & 63U);
  }
  alongX.resize(stencilRowSets_.size() * 8);
  for (std::size_t k = 0; k < stencilRowSets_.size(); ++k) {
    for (std::size_t z = 0; z < 8; ++z) {
      alongX[k * 8 + z] =
          measured[z] == 0 ? std::array<std::uint64_t, 3>{} : dilatedAlongX(measured[z], stencilRowSets_[k]);
    }
  }
  std::uint32_t reachedBlocks = 0;
  for (const StencilRow& row : stencilRows_) {
    for (int z = 0; z < 8; ++z) {
      if (measured[static_cast<std::size_t>(z)] == 0) {
        continue;
      }
      const int zz = z + row.dz;
      const int dzb = zz < 0 ? -1 : (zz >= 8 ? 1 : 0);
      const auto layer = static_cast<std::size_t>(zz - 8 * dzb);
      const std::array<std::uint64_t, 3>& parts = alongX[row.set * 8 + static_cast<std::size_t>(z)];
      for (int dxb = -1; dxb <= 1; ++dxb) {
        const std::uint64_t bx = parts[static_cast<std::size_t>(dxb + 1)];
        if (bx == 0) {
          continue;
        }
        // Along y: whole rows of 8 bits, in this block's row of blocks and the next (or previous) one.
        const unsigned here = static_cast<unsigned>((dxb + 1) + 3 + 9 * (dzb + 1));
        const unsigned next = row.dy >= 0 ? here + 3 : here - 3;
        // |dy| = 8 (a 2-D stencil's reach) moves every row into the next row of blocks.
        const std::uint64_t stay =
            row.dy >= 8 || row.dy <= -8 ? 0 : (row.dy >= 0 ? bx << (8 * row.dy) : bx >> (-8 * row.dy));
        const std::uint64_t cross =
            row.dy > 0 ? bx >> (64 - 8 * row.dy) : (row.dy < 0 ? bx << (64 + 8 * row.dy) : 0);
        reached[here][layer] |= stay;
        reached[next][layer] |= cross;
        reachedBlocks |= (std::uint32_t{stay != 0} << here) | (std::uint32_t{cross != 0} << next);
      }
    }
  }
  for (std::uint32_t rest = reachedBlocks; rest != 0; rest &= rest - 1) {
    const auto d = static_cast<unsigned>(std::countr_zero(rest));
    if (((g.neighbours >> d) & 1U) != 0) {
      std::array<std::uint64_t, 8>& cells = work.touched[touchedOfGroup[d]].cells;
      for (std::size_t layer = 0; layer < 8; ++layer) {
        cells[layer] |= reached[d][layer];
      }
    }
    reached[d] = {};
  }
}

void BandedOgf::copyTouchedCells(Batch& work) const {
  // Banded storage: the touched cells' means and stored variances, blocks in key order.
  std::size_t cells = 0;
  for (const TouchedBlock& block : work.touched) {
    for (const std::uint64_t word : block.cells) {
      cells += static_cast<std::size_t>(std::popcount(word));
    }
  }
  work.meansBefore.resize(cells);
  work.variancesBefore.resize(cells);
  std::size_t visited = 0;
  for (const std::uint32_t t : work.touchedOrder) {
    const TouchedBlock& block = work.touched[t];
    const float* data = block.block->data();
    forEachBit(block.cells, [&](std::size_t l) {
      work.meansBefore[visited] = meanAt(data, l);
      work.variancesBefore[visited] = storedVarianceAt(data, l);
      ++visited;
    });
  }
}

// 5. The updates of eq. (5), colour by colour: the groups of one colour touch disjoint state, and run in
//    parallel when there are threads (applyColourInParallel).
void BandedOgf::applyColours(std::span<const Group> sorted, UpdateStats& stats) {
  Batch& work = scratch_;
  for (std::size_t g0 = 0; g0 < sorted.size();) {
    std::size_t g1 = g0;
    while (g1 < sorted.size() && sorted[g1].colour == sorted[g0].colour) {
      ++g1;
    }
    const std::size_t count = g1 - g0;
    if (config_.threads > 1 && parallelSafe_ && count > 1) {
      applyColourInParallel(sorted, g0, g1, stats);
    } else {
      ring_.resize(kRingSlots * band_.pointers);
      applyRun(sorted.subspan(g0, count), work.sorted, &work.neighbourhoods[g0 * 27], ring_, stats);
    }
    g0 = g1;
  }
}

// Groups [g0, g1) of one colour on config_.threads threads (the calling one among them), each taking the
// next few groups (up to kParallelGroups) as it finishes the ones before: a run of groups keeps applyRun's
// prefetch going from one block to the next, where a group at a time restarts it at every block.
void BandedOgf::applyColourInParallel(std::span<const Group> sorted, std::size_t g0, std::size_t g1,
                                      UpdateStats& stats) {
  Batch& work = scratch_;
  const std::size_t ringSize = kRingSlots * band_.pointers;
  std::atomic<std::size_t> next{g0};
  std::vector<UpdateStats> partial(std::min(static_cast<std::size_t>(config_.threads), g1 - g0));
  // Eight shares a thread at least, for the balance, where the colour has fewer than kParallelGroups each.
  const std::size_t step = std::clamp<std::size_t>((g1 - g0) / (partial.size() * 8), 1, kParallelGroups);
  auto run = [&](std::size_t w) {
    std::vector<float*> ring(ringSize);
    // Counted on the thread's stack: the threads' entries of `partial` share a cache line, and counting
    // there made every update of one thread invalidate the other's line.
    UpdateStats counted;
    for (std::size_t g = next.fetch_add(step); g < g1; g = next.fetch_add(step)) {
      const std::size_t n = std::min(step, g1 - g);
      applyRun(sorted.subspan(g, n), work.sorted, &work.neighbourhoods[g * 27], ring, counted);
    }
    partial[w] = counted;
  };
  pool()->run([&](std::size_t w) {
    if (w < partial.size()) {
      run(w);
    }
  });
  for (const UpdateStats& p : partial) {
    stats.applied += p.applied;
    stats.skipped += p.skipped;
  }
}

// The cells whose stored values changed, gathered a chunk at a time (without a branch on the comparison)
// for flushChanges: where each is (touched block << 9 | position), its mean and stored variance after and
// before.
struct BandedOgf::ChangeChunk {
  static constexpr std::size_t kCells = 512;
  std::array<float, kCells> means1;
  std::array<float, kCells> variances1;
  std::array<float, kCells> means0;
  std::array<float, kCells> variances0;
  std::array<std::uint32_t, kCells> stored1;  // the variances as stored, decoded in flushChanges
  std::array<std::uint32_t, kCells> stored0;
  std::array<std::uint32_t, kCells> where;
  std::array<PublishedState, kCells> now;
  std::array<PublishedState, kCells> was;
  std::array<CellChange, kCells> changes;
  std::size_t n = 0;
};

// 6. Reports the cells whose class or quantised probability changed. In compact storage with threads, each
//    takes a share of the touched layers: the calling thread reports the first share to the sink as it
//    goes, the others keep theirs, which follow in order.
void BandedOgf::reportChanges(ChangeSink& sink) {
  if (!compact()) {
    ChangeChunk chunk;
    collectCellChanges(chunk, sink);
    flushChanges(chunk, sink);
    return;
  }
  const std::size_t layers = scratch_.touchedLayers.size();
  WorkerPool* threads = layers >= kParallelLayersMin ? pool() : nullptr;
  const EvenSplit split{layers, threads != nullptr ? threads->threads() : 1};
  std::vector<ChangeBuffer>& kept = scratch_.keptChanges;
  kept.resize(split.parts);
  const auto report = [&](std::size_t p) {
    ChangeSink& to = p == 0 ? sink : static_cast<ChangeSink&>(kept[p]);
    kept[p].changes.clear();
    ChangeChunk chunk;
    collectLayerChanges(chunk, to, split.begin(p), split.begin(p + 1));
    flushChanges(chunk, to);
  };
  if (threads == nullptr) {
    report(0);
    return;
  }
  threads->run(report);
  for (std::size_t p = 1; p < split.parts; ++p) {
    sink.cellsChanged(kept[p].changes);
  }
}

// Compact storage, a layer at a time (touched layers [e0, e1)): the cells whose mean or code differ from
// the copy, found in vectors, then only those read.
void BandedOgf::collectLayerChanges(ChangeChunk& chunk, ChangeSink& sink, std::size_t e0, std::size_t e1) const {
  const Batch& work = scratch_;
  const std::size_t cellsPerBlock = storage_.cellsPerBlock();
  const std::vector<TouchedLayer>& layers = work.touchedLayers;
  if (e0 < e1) {
    prefetchTouchedLayers(work, e0, e1);
  }
  for (std::size_t e = e0; e < e1; ++e) {
    if (e + 1 < e1 && layers[e + 1].touched != layers[e].touched) {
      prefetchTouchedLayers(work, e + 1, e1);
    }
    const TouchedLayer& layer = layers[e];
    const float* data = work.touched[layer.touched].block->data();
    const float* means = data + layer.layer * kLayerCells;
    const auto* codes =
        reinterpret_cast<const std::uint16_t*>(data + cellsPerBlock) + layer.layer * kLayerCells;
    const float* meansCopy = work.layerMeansBefore.data() + e * kLayerCells;
    const std::uint16_t* codesCopy = work.layerCodesBefore.data() + e * kLayerCells;
    const std::uint32_t base = layer.touched << 9 | layer.layer * static_cast<std::uint32_t>(kLayerCells);
    for (std::uint64_t rest = layer.cells & layerChanges_(means, codes, meansCopy, codesCopy); rest != 0;
         rest &= rest - 1) {
      const auto j = static_cast<std::size_t>(std::countr_zero(rest));
      std::size_t& n = chunk.n;
      chunk.means1[n] = means[j];
      chunk.stored1[n] = codes[j];
      chunk.means0[n] = meansCopy[j];
      chunk.stored0[n] = codesCopy[j];
      chunk.where[n] = base | static_cast<std::uint32_t>(j);
      if (++n == ChangeChunk::kCells) {
        flushChanges(chunk, sink);
      }
    }
  }
}

// Banded storage: every touched cell compared with its copy.
void BandedOgf::collectCellChanges(ChangeChunk& chunk, ChangeSink& sink) {
  const Batch& work = scratch_;
  std::size_t visited = 0;
  for (const std::uint32_t t : work.touchedOrder) {
    const TouchedBlock& block = work.touched[t];
    const float* data = block.block->data();
    forEachBit(block.cells, [&](std::size_t l) {
      const float mean = meanAt(data, l);
      const std::uint32_t stored = storedVarianceAt(data, l);
      std::size_t& n = chunk.n;
      chunk.means1[n] = mean;
      chunk.stored1[n] = stored;
      chunk.means0[n] = work.meansBefore[visited];
      chunk.stored0[n] = work.variancesBefore[visited];
      chunk.where[n] = t << 9 | static_cast<std::uint32_t>(l);
      n += static_cast<std::size_t>(
          !(mean == work.meansBefore[visited] && stored == work.variancesBefore[visited]));
      ++visited;
      if (n == ChangeChunk::kCells) {
        flushChanges(chunk, sink);
      }
    });
  }
}

// The chunk's states after and before in one call each, then compared: the cells whose state differs go to
// the sink.
void BandedOgf::flushChanges(ChangeChunk& chunk, ChangeSink& sink) const {
  const std::size_t n = chunk.n;
  for (std::size_t i = 0; i < n; ++i) {
    chunk.variances1[i] = varianceOfStored(chunk.stored1[i]);
    chunk.variances0[i] = varianceOfStored(chunk.stored0[i]);
  }
  published_.statesOf(std::span(chunk.means1).first(n), std::span(chunk.variances1).first(n),
                      std::span(chunk.now).first(n));
  published_.statesOf(std::span(chunk.means0).first(n), std::span(chunk.variances0).first(n),
                      std::span(chunk.was).first(n));
  std::size_t changed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    CellChange& c = chunk.changes[changed];
    c.key = storage_.cellKey(scratch_.touched[chunk.where[i] >> 9].key, chunk.where[i] & 511U);
    c.mean = chunk.means1[i];
    c.variance = chunk.variances1[i];
    c.quantisedProbability = chunk.now[i].quantisedProbability;
    c.occupancyClass = chunk.now[i].occupancyClass;
    changed += static_cast<std::size_t>(!(chunk.now[i] == chunk.was[i]));
  }
  sink.cellsChanged(std::span(chunk.changes).first(changed));
  chunk.n = 0;
}

void BandedOgf::copyTouchedLayers(Batch& work) {
  // The touched layers in block key order, then their means and codes copied before the updates (by the
  // threads, a share of the layers each, where there are enough).
  std::vector<TouchedLayer>& layers = work.touchedLayers;
  layers.clear();
  for (const std::uint32_t t : work.touchedOrder) {
    const std::array<std::uint64_t, 8>& cells = work.touched[t].cells;
    for (std::uint32_t layer = 0; layer < cells.size(); ++layer) {
      if (cells[layer] != 0) {
        layers.push_back({t, layer, cells[layer]});
      }
    }
  }
  work.layerMeansBefore.resize(layers.size() * kLayerCells);
  work.layerCodesBefore.resize(layers.size() * kLayerCells);
  const std::size_t cellsPerBlock = storage_.cellsPerBlock();
  const auto copyLayers = [&](std::size_t e0, std::size_t e1) {
    if (e0 < e1) {
      prefetchTouchedLayers(work, e0, e1);
    }
    for (std::size_t e = e0; e < e1; ++e) {
      if (e + 1 < e1 && layers[e + 1].touched != layers[e].touched) {
        prefetchTouchedLayers(work, e + 1, e1);
      }
      const float* data = work.touched[layers[e].touched].block->data();
      const auto* codes = reinterpret_cast<const std::uint16_t*>(data + cellsPerBlock);
      std::memcpy(work.layerMeansBefore.data() + e * kLayerCells, data + layers[e].layer * kLayerCells,
                  kLayerCells * sizeof(float));
      std::memcpy(work.layerCodesBefore.data() + e * kLayerCells, codes + layers[e].layer * kLayerCells,
                  kLayerCells * sizeof(std::uint16_t));
    }
  };
  shareOut(layers.size(), layers.size() >= kParallelLayersMin, copyLayers);
}

void BandedOgf::prefetchTouchedLayers(const Batch& work, std::size_t e, std::size_t end) const {
  // The touched layers of the block whose first touched layer is e (up to `end`): a layer's 64 means take
  // four cache lines, their variance codes two.
  const std::vector<TouchedLayer>& layers = work.touchedLayers;
  const std::uint32_t t = layers[e].touched;
  const float* data = work.touched[t].block->data();
  const auto* codes = reinterpret_cast<const std::uint16_t*>(data + storage_.cellsPerBlock());
  for (; e < end && layers[e].touched == t; ++e) {
    const std::size_t first = layers[e].layer * kLayerCells;
    for (std::size_t line = 0; line < 4; ++line) {
      __builtin_prefetch(data + first + line * 16);
    }
    __builtin_prefetch(codes + first);
    __builtin_prefetch(codes + first + 32);
  }
}

void BandedOgf::dropClampedFree(std::span<Group> groups, UpdateStats& stats) {
  // The cells within the stencil of an occupied measurement of the batch, per group (512 bits each): an
  // occupied update raises their means. Blocks without a group hold no measurement and need no bits.
  Batch& work = scratch_;
  std::vector<std::array<std::uint64_t, 8>>& reach = work.occupiedReach;
  reach.assign(groups.size(), {});
  constexpr std::uint32_t kUnknown = BlockKeyTable::kAbsent - 1;
  std::vector<std::uint32_t>& around = work.around;  // per group, the groups of its 27 neighbours once looked up
  around.assign(groups.size() * 27, kUnknown);
  const std::size_t cells = band_.cells;
  for (std::size_t i = 0; i < work.codes.size(); ++i) {
    const std::uint16_t code = work.codes[i];
    if ((code & 1U) == 0) {
      continue;
    }
    const std::uint32_t g = work.groupOf[i];
    const std::size_t local = code >> 1;
    for (std::size_t s = 0; s < cells; ++s) {
      const unsigned d = band_.recordBlock[local * cells + s];
      std::uint32_t& other = around[g * 27 + d];
      if (other == kUnknown) {
        other = work.blocks.find(neighbourOf(groups[g].block, d));
      }
      if (other != BlockKeyTable::kAbsent) {
        const std::uint32_t cell = band_.recordFloat[local * cells + s];  // compact: the stride is 1
        reach[other][cell >> 6] |= std::uint64_t{1} << (cell & 63U);
      }
    }
  }
  const float floorRatio = varianceFloor_ / priorVariance_;  // the kernel's floor, as compactBody has it
  // z = −μ/√(1+s) > c tested as μ² > c²(1+s) with μ < 0, a relative 1e-9 to spare so that rounding in
  // either form cannot drop a measurement applyMeasurement's z would keep (μ² of a float is exact in double).
  const double bound = freeClampZ_ * freeClampZ_ * (1.0 + 1e-9);
  // Measurements [begin, end) tested, those kept moved to the front of the range in order, and the drops
  // of each group counted in `part`: the ranges of the threads are disjoint, and a group may span two.
  const auto dropRange = [&](std::size_t begin, std::size_t end, DropPart& part) {
    part.groupDrops.clear();
    std::size_t dropped = 0;  // on the thread's stack until the end, as `kept`
    std::size_t kept = begin;
    std::uint32_t dropGroup = begin < end ? work.groupOf[begin] : 0;  // the group being read, and its drops
    std::uint32_t droppedInGroup = 0;
    for (std::size_t i = begin; i < end; ++i) {
      // The mean and code of the measurement kDropAhead places on: the blocks are too many to stay in cache.
      if (i + kDropAhead < end) {
        const float* ahead = groups[work.groupOf[i + kDropAhead]].data;
        if (ahead != nullptr) {
          const std::size_t local = work.codes[i + kDropAhead] >> 1;
          __builtin_prefetch(ahead + local);
          __builtin_prefetch(reinterpret_cast<const std::uint16_t*>(ahead + storage_.cellsPerBlock()) + local);
        }
      }
      const std::uint16_t code = work.codes[i];
      const std::uint32_t g = work.groupOf[i];
      const float* data = groups[g].data;  // null for a new block: its cells are at the prior, z = 0
      const std::size_t local = code >> 1;
      // Without a branch on the outcome, which a scan's measurements leave unpredictable (about half go).
      unsigned drop = 0;
      if (data != nullptr) {
        const float ratio =
            decodeVarianceRatio(reinterpret_cast<const std::uint16_t*>(data + storage_.cellsPerBlock())[local]);
        const auto mean = static_cast<double>(data[local]);
        drop = static_cast<unsigned>((code & 1U) == 0) &
               static_cast<unsigned>(((reach[g][local >> 6] >> (local & 63U)) & 1U) == 0) &
               static_cast<unsigned>(ratio >= floorRatio) & static_cast<unsigned>(mean < 0.0) &
               static_cast<unsigned>(mean * mean > bound * (1.0 + static_cast<double>(priorVariance_ * ratio)));
      }
      if (g != dropGroup) {
        if (droppedInGroup != 0) {
          part.groupDrops.emplace_back(dropGroup, droppedInGroup);
        }
        dropGroup = g;
        droppedInGroup = 0;
      }
      droppedInGroup += drop;
      dropped += drop;
      work.codes[kept] = code;
      work.groupOf[kept] = g;
      kept += 1U - drop;
    }
    if (droppedInGroup != 0) {
      part.groupDrops.emplace_back(dropGroup, droppedInGroup);
    }
    part.kept = kept - begin;
    part.dropped = dropped;
  };
  const std::size_t n = work.codes.size();
  // Shared among the threads where there are enough measurements to pay for waking them.
  WorkerPool* threads = n >= kParallelBatchMin ? pool() : nullptr;
  const EvenSplit split{n, threads != nullptr ? threads->threads() : 1};
  std::vector<DropPart>& parts = work.dropParts;
  parts.resize(split.parts);
  if (threads != nullptr) {
    threads->run([&](std::size_t p) { dropRange(split.begin(p), split.begin(p + 1), parts[p]); });
  } else {
    dropRange(0, n, parts[0]);
  }
  std::size_t kept = 0;
  for (std::size_t p = 0; p < split.parts; ++p) {
    const DropPart& part = parts[p];
    closeUp(split.begin(p), part.kept, kept);  // the ranges' kept measurements, in order
    kept += part.kept;
    for (const auto& [g, dropped] : part.groupDrops) {
      groups[g].end -= dropped;
    }
    stats.skipped += part.dropped;
    stats.skippedEarly += part.dropped;
  }
  work.codes.resize(kept);
  work.groupOf.resize(kept);
}

void BandedOgf::applyRun(std::span<const Group> groups, std::span<const std::uint16_t> codes,
                         float* const* neighbourhoods, std::span<float*> ring, UpdateStats& stats) {
  // The groups' measurements are consecutive in `codes`; measurement i's records are in ring slot i mod
  // kRingSlots, found kPrefetchAhead measurements earlier.
  const std::size_t cells = band_.pointers;
  const std::size_t first = groups.front().begin;
  const std::size_t last = groups.back().end;
  const auto slot = [&](std::size_t i) { return ring.data() + (i & (kRingSlots - 1)) * cells; };
  std::size_t aheadGroup = 0;
  const auto locateAhead = [&](std::size_t i) {
    while (i >= groups[aheadGroup].end) {
      ++aheadGroup;
    }
    locate_(neighbourhoods + aheadGroup * 27, static_cast<std::size_t>(codes[i] >> 1), band_, slot(i));
  };
  for (std::size_t i = first; i < std::min(first + kPrefetchAhead, last); ++i) {
    locateAhead(i);
  }
  for (std::size_t i = first; i < last; ++i) {
    if (i + kPrefetchAhead < last) {
      locateAhead(i + kPrefetchAhead);
    }
    if (applyMeasurement(slot(i), (codes[i] & 1U) != 0 ? 1 : -1)) {
      ++stats.applied;
    } else {
      ++stats.skipped;
    }
  }
}

void BandedOgf::markOccupied(Block& block, std::span<const std::uint16_t> codes) {
  const std::span<std::uint8_t> marks = block.marks();
  for (const std::uint16_t code : codes) {
    if ((code & 1U) != 0) {
      marks[code >> 1] = CellMark::kHit;
    }
  }
}

bool BandedOgf::applyMeasurement(float* const* records, int y) {
  const float* self = records[band_.self];
  double var = 0.0;
  double inverseScale = 0.0;
  if (compact()) {
    const std::uint16_t code = *reinterpret_cast<const std::uint16_t*>(records[band_.cells + band_.self]);
    var = static_cast<double>(priorVariance_ * decodeVarianceRatio(code));
    inverseScale = inverseScales_[code];
  } else {
    var = static_cast<double>(self[1]);
    inverseScale = 1.0 / std::sqrt(1.0 + var);
  }
  const double tolerance = config_.skipTolerance;
  const double z = static_cast<double>(y) * static_cast<double>(self[0]) * inverseScale;
  if (z > (y < 0 ? freeClampZ_ : clampZ_)) {
    return false;
  }
  const ProbitUpdate u = probitUpdateScaled(y, inverseScale, z, (*lambda_)(z));
  if (tolerance > 0.0 && std::abs(var * u.meanGain) < tolerance && var * var * u.covShrink < tolerance) {
    return false;
  }
  // Eq. (5) inside the band: m += Σ[:, i]·gain, Σ_jk −= shrink·Σ_ji·Σ_ki for every stored pair, in float.
  kernel_(records, {static_cast<float>(u.meanGain), static_cast<float>(u.covShrink), varianceFloor_}, band_);
  return true;
}

BandedOgf BandedOgf::withCovarianceStorage(CovarianceStorage storage) const {
  FilterConfig config = config_;
  config.covariance = storage;
  BandedOgf out(config);  // config_ is resolved and valid; only the storage differs
  const double v0 = prior_.variance();
  std::vector<float> values;
  for (const CellKey& key : storage_.sortedKeys()) {
    const Block* b = storage_.find(key);
    values.clear();
    for (std::size_t l = 0; l < b->cells(); ++l) {
      const Moments c = momentsAt(b->data(), l);
      values.push_back(c.mean);
      values.push_back(c.variance);
      if (storage == CovarianceStorage::kBanded) {
        const CellKey cell = storage_.cellKey(key, l);
        for (const CellKey& o : stencil_.forwardOffsets()) {
          const double other = estimate(cell + o).variance;
          values.push_back(static_cast<float>(prior_(o) * (static_cast<double>(c.variance) / v0) * (other / v0)));
        }
      }
    }
    static_cast<void>(out.restoreBlock(key, values, b->marks()));  // same keys, sizes of `out`'s layout
  }
  return out;
}

Status BandedOgf::adoptPolicy(const FilterConfig& config) {
  FilterConfig next = config_;
  next.occupiedThreshold = config.occupiedThreshold;
  next.freeThreshold = config.freeThreshold;
  next.skipTolerance = config.skipTolerance;
  next.clampZ = config.clampZ;
  next.freeClampZ = config.freeClampZ;
  next.occupiedPriority = config.occupiedPriority;
  next.freeReleaseCount = config.freeReleaseCount;
  next.threads = config.threads;
  // Only the policy changed: the structure (and its prior's certificate) is the map's own.
  if (auto st = next.validatePolicy(); !st) {
    return st;
  }
  config_ = next;
  derivePolicyState();
  return okStatus();
}

void BandedOgf::derivePolicyState() {
  published_ = PublishedStateRule(config_.occupiedThreshold, config_.freeThreshold);
  clampZ_ = config_.clampZ > 0.0 ? config_.clampZ : std::numeric_limits<double>::infinity();
  freeClampZ_ = config_.clampZ > 0.0 && config_.freeClampZ > 0.0 ? std::min(clampZ_, config_.freeClampZ) : clampZ_;
}

CellEstimate BandedOgf::estimate(const CellKey& cell) const {
  const Block* b = storage_.find(blockKeyOf(cell));
  if (b == nullptr || (config_.dimensions == 2 && cell.z != 0)) {
    return {0.0, prior_.variance(), false};
  }
  const Moments c = momentsAt(b->data(), localIndexOf(cell));
  return {static_cast<double>(c.mean), static_cast<double>(c.variance), true};
}

double BandedOgf::covariance(const CellKey& a, const CellKey& b) const {
  if (a == b) {
    return estimate(a).variance;
  }
  const CellKey o = b - a;
  const bool forward = isForward(o);
  const CellKey& owner = forward ? a : b;
  const int slot = stencil_.forwardIndexOf(forward ? o : a - b);
  if (slot < 0) {
    return 0.0;
  }
  if (compact()) {
    // The prior's covariance scaled by both cells' variance ratios (FilterConfig::covariance).
    const double v0 = prior_.variance();
    return prior_(o) * (estimate(a).variance / v0) * (estimate(b).variance / v0);
  }
  const Block* blk = storage_.find(blockKeyOf(owner));
  if (blk == nullptr) {
    return prior_(o);
  }
  return static_cast<double>(
      blk->data()[localIndexOf(owner) * floatsPerCell() + 2 + static_cast<std::size_t>(slot)]);
}

void BandedOgf::forEachCell(const std::function<void(const CellKey&, float, float)>& visit) const {
  const int side = kBlockSide;
  const int zSide = config_.dimensions == 3 ? kBlockSide : 1;
  for (const CellKey& key : storage_.sortedKeys()) {
    const float* d = storage_.find(key)->data();
    for (int x = 0; x < side; ++x) {
      for (int y = 0; y < side; ++y) {
        for (int z = 0; z < zSide; ++z) {
          const auto l = static_cast<std::size_t>(x + side * (y + side * z));
          const Moments c = momentsAt(d, l);
          visit(CellKey{key.x * side + x, key.y * side + y, key.z * side + z}, c.mean, c.variance);
        }
      }
    }
  }
}

std::size_t BandedOgf::memoryBytes() const {
  return storage_.memoryBytes() + sizeof(*this) +
         stencil_.offsets().size() * (sizeof(CellKey) + 3 * sizeof(std::int32_t) + 2 * sizeof(std::int16_t)) +
         stencil_.pairs().size() * sizeof(StencilPair);
}

std::uint64_t BandedOgf::blockHash(const CellKey& key, const Block& block) const {
  if (!block.hashKnown()) {
    block.setHash(blockChecksum(key, block.values(), block.marks()));
  }
  return block.hash();
}

std::uint64_t BandedOgf::blockHash(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? 0 : blockHash(blockKey, *b);
}

BlockHashSum BandedOgf::blockHashSum() const {
  // Known hashes are summed as they come; the blocks changed since their last hash (those a scan touched)
  // are hashed four at a time (blockChecksums), the rest one by one.
  BlockHashSum total;
  std::array<BlockBytes, 4> pending;
  std::array<const Block*, 4> pendingBlocks{};
  std::size_t waiting = 0;
  storage_.forEachBlock([&](const CellKey& key, const Block& block) {
    ++total.blocks;
    if (block.hashKnown()) {
      total.sum += block.hash();
      return;
    }
    pending[waiting] = {key, block.values(), block.marks()};
    pendingBlocks[waiting] = &block;
    if (++waiting == pending.size()) {
      const std::array<std::uint64_t, 4> hashes = blockChecksums(pending);
      for (std::size_t j = 0; j < hashes.size(); ++j) {
        pendingBlocks[j]->setHash(hashes[j]);
        total.sum += hashes[j];
      }
      waiting = 0;
    }
  });
  for (std::size_t j = 0; j < waiting; ++j) {
    total.sum += blockHash(pending[j].key, *pendingBlocks[j]);
  }
  return total;
}

std::uint64_t BandedOgf::checksum(const BlockHashSum& heldElsewhere) const {
  MapChecksum sum;
  sum.addValue(config_.dimensions);
  sum.addValue(config_.resolution);
  sum.addValue(*config_.kernelSigma);
  sum.addValue(*config_.kernelAmplitude);
  sum.addValue(*config_.stencilRadius);
  sum.addValue(*config_.taperSupport);
  if (config_.covariance != CovarianceStorage::kBanded) {
    sum.addValue(static_cast<int>(config_.covariance));
  }
  BlockHashSum blocks = blockHashSum();
  blocks.sum += heldElsewhere.sum;
  blocks.blocks += heldElsewhere.blocks;
  sum.addValue(blocks.blocks);
  sum.addValue(blocks.sum);
  return sum.value();
}

std::vector<float> BandedOgf::blockValues(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  if (b == nullptr) {
    return {};
  }
  if (!compact()) {
    return {b->values().begin(), b->values().end()};
  }
  std::vector<float> values;
  values.reserve(floatsPerBlock());
  for (std::size_t l = 0; l < b->cells(); ++l) {
    const Moments c = momentsAt(b->data(), l);
    values.push_back(c.mean);
    values.push_back(c.variance);
  }
  return values;
}

std::span<const std::uint8_t> BandedOgf::blockMarks(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? std::span<const std::uint8_t>{} : b->marks();
}

Status BandedOgf::checkRestorable(const CellKey& blockKey, std::size_t values, std::size_t expected,
                                  std::size_t marks) const {
  const std::string block =
      "block " + std::to_string(blockKey.x) + "," + std::to_string(blockKey.y) + "," + std::to_string(blockKey.z);
  if (marks != 0 && marks != storage_.cellsPerBlock()) {
    return Error::inputDamaged(block + ": " + std::to_string(marks) + " cell marks, expected " +
                               std::to_string(storage_.cellsPerBlock()));
  }
  if (values != expected) {
    return Error::inputDamaged(block + ": " + std::to_string(values) + " values, expected " + std::to_string(expected));
  }
  if (config_.dimensions == 2 && blockKey.z != 0) {
    return Error::inputDamaged("block z = " + std::to_string(blockKey.z) + " in a 2-D map");
  }
  if (storage_.find(blockKey) != nullptr) {
    return Error::inputDamaged(block + " appears twice");
  }
  return okStatus();
}

std::span<const float> BandedOgf::storedValues(const CellKey& blockKey) const {
  const Block* b = storage_.find(blockKey);
  return b == nullptr ? std::span<const float>{} : b->values();
}

Status BandedOgf::restoreStoredBlock(const CellKey& blockKey, std::span<const float> stored,
                                     std::span<const std::uint8_t> marks) {
  if (auto st = checkRestorable(blockKey, stored.size(), storage_.floatsPerBlock(), marks.size()); !st) {
    return st;
  }
  bool fresh = false;
  Block& b = storage_.obtain(blockKey, fresh);
  std::copy(stored.begin(), stored.end(), b.data());
  std::copy(marks.begin(), marks.end(), b.marks().begin());
  return okStatus();
}

Status BandedOgf::restoreBlock(const CellKey& blockKey, std::span<const float> values,
                               std::span<const std::uint8_t> marks) {
  if (!compact()) {
    return restoreStoredBlock(blockKey, values, marks);  // banded storage exchanges its blocks as stored
  }
  if (auto st = checkRestorable(blockKey, values.size(), floatsPerBlock(), marks.size()); !st) {
    return st;
  }
  bool fresh = false;
  Block& b = storage_.obtain(blockKey, fresh);
  auto* codes = reinterpret_cast<std::uint16_t*>(b.data() + b.cells());
  for (std::size_t l = 0; l < b.cells(); ++l) {
    b.data()[l] = values[2 * l];
    codes[l] = encodeVarianceRatio(values[2 * l + 1] / priorVariance_);
  }
  std::copy(marks.begin(), marks.end(), b.marks().begin());
  return okStatus();
}

}  // namespace ogf::filter
