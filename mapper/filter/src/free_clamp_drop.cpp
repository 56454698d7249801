// Between stages 1 and 2 of BandedOgf::update: the free measurements certain to be skipped, dropped
// before the batch is ordered (compact storage; the map is the same bit for bit).

#include <cstdint>
#include <span>
#include <vector>

#include "banded_batch.hpp"
#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {

namespace {

// dropClampedFree asks for the mean and code of the measurement this many places ahead.
constexpr std::size_t kDropAhead = 96;

}  // namespace

void BandedOgf::dropClampedFree(std::span<Group> groups, UpdateStats& stats) {
  // The cells within the stencil of an occupied measurement of the batch, per group (512 bits each): an
  // occupied update raises their means. Blocks without a group hold no measurement and need no bits.
  Batch& work = scratch_->batch;
  banded::DropScratch& own = scratch_->drop;
  std::vector<std::array<std::uint64_t, 8>>& reach = own.occupiedReach;
  reach.assign(groups.size(), {});
  constexpr std::uint32_t kUnknown = BlockKeyTable::kAbsent - 1;
  std::vector<std::uint32_t>& around =
      own.around;  // per group, the groups of its 27 neighbours once looked up
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
        other = work.blocks.find(banded::neighbourOf(groups[g].block, d));
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
  const auto dropRange = [&](std::size_t begin, std::size_t end, banded::DropScratch::Part& part) {
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
          __builtin_prefetch(reinterpret_cast<const std::uint16_t*>(ahead + storage_.cellsPerBlock()) +
                             local);
        }
      }
      const std::uint16_t code = work.codes[i];
      const std::uint32_t g = work.groupOf[i];
      const float* data = groups[g].data;  // null for a new block: its cells are at the prior, z = 0
      const std::size_t local = code >> 1;
      // Without a branch on the outcome, which a scan's measurements leave unpredictable (about half go).
      unsigned drop = 0;
      if (data != nullptr) {
        const float ratio = decodeVarianceRatio(
            reinterpret_cast<const std::uint16_t*>(data + storage_.cellsPerBlock())[local]);
        const auto mean = static_cast<double>(data[local]);
        drop =
            static_cast<unsigned>((code & 1U) == 0) &
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
  std::vector<banded::DropScratch::Part>& parts = own.parts;
  parts.resize(split.parts);
  if (threads != nullptr) {
    threads->run([&](std::size_t p) { dropRange(split.begin(p), split.begin(p + 1), parts[p]); });
  } else {
    dropRange(0, n, parts[0]);
  }
  std::size_t kept = 0;
  for (std::size_t p = 0; p < split.parts; ++p) {
    const banded::DropScratch::Part& part = parts[p];
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

}  // namespace ogf::filter
