// The cells one scan has marked free or occupied, kept as bits in 8×8×8 bricks found through a small
// open-addressing table. Consecutive cells of a ray mostly fall in the brick of the previous one, so a mark
// is usually a shift, a compare and an OR on a cache-hot brick; the table is only consulted when a ray
// enters another brick. Read back brick by brick (BrickOrder) with occupied winning over free (Sun et al.
// Sec. VI-B): the filter's blocks are these bricks, so it gets each block's measurements together.
// Buffers are reused from scan to scan: no allocation in steady state.
#pragma once

#include <ogf/core/cell_key.hpp>
#include <ogf/core/measurement.hpp>
#include <ogf/fusion/ray_caster.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace ogf::fusion {

// The order of a scan's measurements: by brick (cell >> 3 on each axis, as the filter's blocks), bricks in
// CellKey order, and by CellKey within a brick.
struct BrickOrder {
  bool operator()(const CellKey& a, const CellKey& b) const {
    const CellKey ba{a.x >> 3, a.y >> 3, a.z >> 3};
    const CellKey bb{b.x >> 3, b.y >> 3, b.z >> 3};
    return ba == bb ? a < b : ba < bb;
  }
};

class CellMarks {
 public:
  void clear();

  void markFree(const CellKey& k) { mark(k, &Brick::free); }
  void markOccupied(const CellKey& k) { mark(k, &Brick::occupied); }
  // Marks every cell of the ray free (the same cells as iterating `ray`): the hot loop of a scan. It runs
  // the traversal itself on local copies of the iterator's state, so nothing is spilled to memory, and
  // collects the cells of one brick word (one local x) in a register, storing it when x steps or the ray
  // leaves the brick; a store per cell would chain each mark to the last through memory.
  void markFree(const RayCaster& ray);

  // Appends one measurement per marked cell to `out`, in BrickOrder; occupied where both were marked.
  void appendSorted(std::vector<Measurement>& out);

  std::size_t brickCount() const { return used_; }

 private:
  using Bits = std::array<std::uint64_t, 8>;  // word = local x, bit = 8·(local y) + local z
  struct Brick {
    Bits free;
    Bits occupied;
    CellKey key;  // brick coordinates: cell >> 3
  };
  struct Slot {
    CellKey key;
    std::uint32_t brick = kEmpty;
  };
  static constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();

  // Same brick iff the coordinates agree above their 3 low bits (two's complement, so this holds for
  // negative cells too): a few instructions, and a predictable branch, since the brick changes only every
  // few cells of a ray.
  static bool sameBrick(const CellKey& a, const CellKey& b) {
    return (((a.x ^ b.x) | (a.y ^ b.y) | (a.z ^ b.z)) & ~7) == 0;
  }
  static void setBit(Bits& bits, const CellKey& k) {
    const auto bit = static_cast<unsigned>(((k.y & 7) << 3) | (k.z & 7));
    bits[static_cast<std::size_t>(k.x & 7)] |= std::uint64_t{1} << bit;
  }

  void mark(const CellKey& k, Bits Brick::*which) {
    if (!sameBrick(k, last_cell_)) {
      last_brick_ = brickAt(k);
      last_cell_ = k;
    }
    setBit(last_brick_->*which, k);
  }

  // The "no brick yet" cell: it shares a brick only with x in [INT32_MIN, INT32_MIN + 7], which is out of
  // bounds for CellMarks (MeasurementSet keeps cells within 2^30 of the origin).
  static constexpr CellKey kNoCell{std::numeric_limits<std::int32_t>::min(), 0, 0};

  // Brick coordinates as three integers, not a CellKey: packing one into registers for the call went
  // through the stack and stalled on store forwarding.
  std::uint32_t brickIndex(std::int32_t bx, std::int32_t by, std::int32_t bz);
  // Arithmetic shifts floor negative coordinates (C++20 defines them).
  Brick* brickAt(const CellKey& k) { return &bricks_[brickIndex(k.x >> 3, k.y >> 3, k.z >> 3)]; }
  std::uint32_t tableIndex(CellKey b);
  void grow();

  std::vector<Brick> bricks_;  // [0, used_) in use this scan; the rest kept for reuse
  std::size_t used_ = 0;
  std::vector<Slot> table_;    // power-of-two size, at most half full
  static constexpr unsigned kRecentBits = 9;
  std::array<Slot, std::size_t{1} << kRecentBits> recent_{};  // direct-mapped cache in front of table_
  CellKey last_cell_ = kNoCell;  // a cell of the brick of the last mark, and where that brick is
  Brick* last_brick_ = nullptr;
  std::vector<std::uint32_t> order_;  // scratch for appendSorted
};

}  // namespace ogf::fusion
