// Storage of PublishedMap: the published cells of one 8 × 8 × 1 slab (x and y floor-divided by 8, z as is),
// packed. A 64-bit mask says which of the slab's cells were published; only those are stored, 7 bytes each
// (probability, class, variance) in local-index order, so a cell's place is the number of mask bits below
// it. Slabs flat in z serve 2-D maps (z = 0) and 3-D maps alike without knowing which; packing keeps a
// partly published slab (a wall crossing it, the edge of the swept space) at 7 bytes per published cell
// rather than the slab's 64.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

#include "ogf/delta/published_cell.hpp"

namespace ogf::delta {

// What a slab stores of a cell: the published fields without the key (the slab and the mask give it).
// Default-constructed it is the prior, what a cell never published reads as.
struct PublishedValue {
  std::int16_t probability = kPriorProbability;
  std::int8_t cell_class = ogf::map_delta_t::CLASS_UNKNOWN;
  float variance = 0.0f;
};

class PublishedBlock {
 public:
  static constexpr std::int32_t kSide = 8;
  static constexpr std::size_t kCells = kSide * kSide;
  // Bytes per stored cell: probability (2), class (1), variance (4), unaligned.
  static constexpr std::size_t kCellBytes = 7;
  // Storage grows in steps of this many cells: few reallocations per slab, at most 7 cells unused.
  static constexpr std::size_t kGrowth = 8;

  // The slab holding a cell and the cell's index in it (x fastest). C++20 defines >> on negative integers
  // as an arithmetic shift, a floor division by 8, so negative keys need no special case.
  static CellKey blockKeyOf(const CellKey& cell) { return {cell.x >> 3, cell.y >> 3, cell.z}; }
  static unsigned localIndexOf(const CellKey& cell) { return static_cast<unsigned>((cell.x & 7) + 8 * (cell.y & 7)); }
  static CellKey cellKey(const CellKey& blockKey, unsigned local) {
    return {blockKey.x * kSide + static_cast<std::int32_t>(local % kSide),
            blockKey.y * kSide + static_cast<std::int32_t>(local / kSide), blockKey.z};
  }

  std::uint64_t present() const { return present_; }
  bool has(unsigned local) const { return (present_ >> local & 1U) != 0; }
  std::size_t size() const { return bitCount(present_); }
  // Cells the storage has room for: size() rounded up to kGrowth (derived, so the slab stays 16 bytes).
  std::size_t capacity() const { return (size() + kGrowth - 1) / kGrowth * kGrowth; }

  // The value of a present cell.
  PublishedValue at(unsigned local) const;
  // The value of the cell, nullopt when absent.
  std::optional<PublishedValue> find(unsigned local) const {
    return has(local) ? std::optional<PublishedValue>(at(local)) : std::nullopt;
  }
  // Stores the cell's value; returns the value it replaces, nullopt when the cell was absent.
  std::optional<PublishedValue> put(unsigned local, const PublishedValue& value);

  // The same in steps, for a caller that reads a cell before it writes it (one rank for both): the place of
  // cell `local` among the stored cells (how many present cells precede it), the value at a present cell's
  // place, a present cell's value replaced, and an absent cell inserted at its place (returns by how many
  // cells the storage grew: 0 or kGrowth).
  std::size_t rank(unsigned local) const { return bitCount(present_ & ((std::uint64_t{1} << local) - 1)); }
  PublishedValue valueAt(std::size_t rank) const;
  void replaceAt(std::size_t rank, const PublishedValue& value);
  std::size_t insertAt(unsigned local, std::size_t rank, const PublishedValue& value);

 private:
  // The set bits of a word in a few inline instructions: std::popcount is a library call on the x86-64
  // baseline (no POPCNT), a visible part of a delta's per-cell cost.
  static std::size_t bitCount(std::uint64_t v) {
    v -= (v >> 1) & 0x5555555555555555ULL;
    v = (v & 0x3333333333333333ULL) + ((v >> 2) & 0x3333333333333333ULL);
    v = (v + (v >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
    return static_cast<std::size_t>((v * 0x0101010101010101ULL) >> 56);
  }

  std::uint64_t present_ = 0;
  std::unique_ptr<std::byte[]> cells_;
};

}  // namespace ogf::delta
