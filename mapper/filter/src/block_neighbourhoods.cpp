// Stage 3 of BandedOgf::update: every block the batch touches found or allocated, the groups'
// neighbourhoods of block data gathered, and the occupied measurements marked.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>

#include "banded_batch.hpp"

namespace ogf::filter {

namespace {

constexpr unsigned kOwnBlock = 13;  // (0, 0, 0) in the 3×3×3 neighbourhood's numbering
// findNeighbourhoods': table slots, then look-ups and headers, this many groups ahead.
constexpr std::size_t kGroupSlotAhead = 16;
constexpr std::size_t kGroupLookAhead = 6;

}  // namespace

// 3. Every block the batch touches, allocated up front (serially, in order; the new ones then initialised
//    on all threads); each group's neighbourhood of block data kept for applyColours, the blocks' numbers
//    for recordChangeableCells, and the occupied measurements marked (OccupiedPriority::kMap).
void BandedOgf::obtainNeighbourhoods(std::span<const Group> sorted, UpdateStats& stats) {
  Batch& work = scratch_->batch;
  banded::NeighbourhoodScratch& own = scratch_->neighbourhoods;
  work.neighbourhoods.assign(sorted.size() * 27, nullptr);
  work.groupTouched.resize(sorted.size() * 27);
  own.freshBlocks.clear();
  own.freshOwnGroups.clear();
  try {
    findNeighbourhoods(sorted);
  } catch (...) {
    initialiseBlocks(own.freshBlocks);  // none left unwritten in the map
    throw;
  }
  initialiseBlocks(own.freshBlocks);
  stats.blocksAllocated += own.freshBlocks.size();
  for (const std::uint32_t r : own.freshOwnGroups) {
    markOccupied(*work.touched[work.groupTouched[r * 27 + kOwnBlock]].block, codesOf(sorted[r]));
  }
}

std::span<const std::uint16_t> BandedOgf::codesOf(const Group& g) const {
  return std::span<const std::uint16_t>(scratch_->batch.sorted).subspan(g.begin, g.end - g.begin);
}

// obtainNeighbourhoods' pass over the groups: their blocks looked up, or allocated unwritten (listed in
// NeighbourhoodScratch::freshBlocks), and the occupied measurements of the groups whose block is not new
// marked.
void BandedOgf::findNeighbourhoods(std::span<const Group> sorted) {
  Batch& work = scratch_->batch;
  banded::NeighbourhoodScratch& own = scratch_->neighbourhoods;
  // The neighbourhoods ahead: the table slots of their blocks asked of the CPU kGroupSlotAhead groups
  // early, the blocks looked up (and numbered) kGroupLookAhead groups early and their headers asked for,
  // as each is marked written below. A scan's blocks are far more than the cache holds.
  const auto prefetchSlots = [&](const Group& g) {
    for (std::uint32_t rest = g.neighbours; rest != 0; rest &= rest - 1) {
      storage_.prefetch(banded::neighbourOf(g.block, static_cast<unsigned>(std::countr_zero(rest))));
    }
  };
  const auto lookUpNeighbourhood = [&](std::size_t q) {
    const Group& g = sorted[q];
    for (std::uint32_t rest = g.neighbours; rest != 0; rest &= rest - 1) {
      const auto d = static_cast<unsigned>(std::countr_zero(rest));
      const std::uint32_t t = lookUp(banded::neighbourOf(g.block, d));
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
        const CellKey key = banded::neighbourOf(g.block, d);
        const std::uint32_t t = work.groupTouched[r * 27 + d];
        TouchedBlock& touched = work.touched[t];
        if (!touched.written) {
          if (touched.block == nullptr) {
            touched.block = &storage_.obtainUnwritten(key, touched.fresh);
            if (touched.fresh) {
              own.freshBlocks.push_back(touched.block);
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
            own.freshOwnGroups.push_back(static_cast<std::uint32_t>(r));
          } else {
            markOccupied(block, codesOf(g));
          }
        }
      }
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

}  // namespace ogf::filter
