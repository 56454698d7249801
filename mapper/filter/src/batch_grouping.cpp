// Stage 1 of BandedOgf::update: the batch grouped by block, on one thread or, for a scan-sized batch in
// runs of blocks, shared among the filter threads with the same result.

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "banded_batch.hpp"

namespace ogf::filter {

namespace {

// prefetchRunsAhead asks for the table slot, the header and the marks of the block this many runs ahead.
constexpr std::size_t kRunSlotAhead = 8;
constexpr std::size_t kRunHeaderAhead = 4;
constexpr std::size_t kRunMarksAhead = 2;
static_assert(kRunMarksAhead < kRunHeaderAhead && kRunHeaderAhead < kRunSlotAhead);
constexpr std::size_t kMinRunForPrefetch = 8;  // measurements per run, on average

// The colour of a block in the 2×2×2 checkerboard (banded_ogf.hpp, determinism).
std::uint32_t colourOf(const CellKey& blockKey) {
  return static_cast<std::uint32_t>((blockKey.x & 1) | ((blockKey.y & 1) << 1) | ((blockKey.z & 1) << 2));
}

}  // namespace

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

// Runs of consecutive measurements in one block (a scan's come block by block), each run's block looked up
// once: where each starts, then the batch's end.
inline void BandedOgf::findRuns(std::span<const Measurement> batch) {
  std::vector<std::size_t>& runs = scratch_->grouping.runs;
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
                                         std::span<const Block*> foundAhead) const {
  const std::vector<std::size_t>& runs = scratch_->grouping.runs;
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
  Batch& work = scratch_->batch;
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
  Batch& work = scratch_->batch;
  banded::GroupingScratch& own = scratch_->grouping;
  std::size_t i = own.runs[r];
  const std::size_t end = own.runs[r + 1];
  for (; i < end && !acceptable(batch[i]); ++i) {
    ++stats.rejected;
  }
  if (i == end) {
    return;
  }
  const CellKey block = blockKeyOf(batch[i].key);
  bool inserted = false;
  const std::uint32_t g =
      work.blocks.findOrInsert(block, static_cast<std::uint32_t>(groups.size()), inserted);
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
  Batch& work = scratch_->batch;
  banded::GroupingScratch& own = scratch_->grouping;
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
  const std::size_t runCount = own.runs.size() - 1;
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
  Batch& work = scratch_->batch;
  banded::GroupingScratch& own = scratch_->grouping;
  const std::size_t n = batch.size();
  const EvenSplit split{n, threads.threads()};
  std::vector<banded::GroupingScratch::Part>& parts = own.parts;
  parts.resize(split.parts);
  const bool readsExisting = readsBlocks();
  const auto runBlock = [&](std::size_t i) { return blockKeyOf(batch[i].key); };
  threads.run([&](std::size_t p) {
    banded::GroupingScratch::Part& part = parts[p];
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
  std::vector<std::size_t>& runs = own.runs;
  runs.clear();
  std::vector<Block*>& blocksOfRuns = own.runBlocks;
  blocksOfRuns.clear();
  std::vector<std::uint8_t>& acceptableRuns = own.runAcceptable;
  acceptableRuns.clear();
  for (const banded::GroupingScratch::Part& part : parts) {
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
  std::vector<std::uint32_t>& groupOfRun = own.runGroups;
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
    banded::GroupingScratch::Part& part = parts[p];
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
  for (const banded::GroupingScratch::Part& part : parts) {
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
  Batch& work = scratch_->batch;
  if (from == to) {
    return;
  }
  std::copy_n(work.codes.begin() + static_cast<std::ptrdiff_t>(from), count,
              work.codes.begin() + static_cast<std::ptrdiff_t>(to));
  std::copy_n(work.groupOf.begin() + static_cast<std::ptrdiff_t>(from), count,
              work.groupOf.begin() + static_cast<std::ptrdiff_t>(to));
}

}  // namespace ogf::filter
