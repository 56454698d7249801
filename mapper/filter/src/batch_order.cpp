// Stage 2 of BandedOgf::update: the batch placed in the deterministic order of application.

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "banded_batch.hpp"

namespace ogf::filter {

namespace {

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

}  // namespace

// 2. The deterministic order: colour, block key, position in the block (then y). Groups are sorted (by
//    colour alone, stably, when they came in key order, as a scan's do), the measurements placed by group,
//    then each group's few codes sorted.
std::vector<BandedOgf::Group> BandedOgf::orderGroups(std::vector<Group>& groups) {
  Batch& work = scratch_->batch;
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
      sortCodes(
          std::span<std::uint16_t>(work.sorted).subspan(sorted[r].begin, sorted[r].end - sorted[r].begin));
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
  std::vector<std::size_t>& from = scratch_->order.groupFrom;
  from.resize(groups.size());
  std::size_t source = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    from[g] = source;
    source += groups[g].end - groups[g].begin;
  }
  const auto placeGroups = [&](std::size_t r0, std::size_t r1) {
    for (std::size_t r = r0; r < r1; ++r) {
      std::copy_n(work.codes.begin() + static_cast<std::ptrdiff_t>(from[order[r]]),
                  sorted[r].end - sorted[r].begin,
                  work.sorted.begin() + static_cast<std::ptrdiff_t>(sorted[r].begin));
    }
    sortGroupCodes(r0, r1);
  };
  shareOut(sorted.size(), placed >= kParallelBatchMin, placeGroups);
  return sorted;
}

}  // namespace ogf::filter
