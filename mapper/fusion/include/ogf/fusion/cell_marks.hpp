// The cells one scan has marked free or occupied, as bits in 8×8×8 bricks (a word per local x, in it bit
// 8·(local y) + local z), read back brick by brick (BrickOrder) with occupied winning over free (Sun et al.
// Sec. VI-B): the filter's blocks are these bricks, so it gets each block's measurements together.
//
// Two ways to keep the bricks, with the same result:
// - Hashed: bricks found through a small open-addressing table as the rays reach them, each ray traversed
//   as it comes (markFree). Consecutive cells of a ray mostly fall in the brick of the previous one, so a
//   mark is usually a shift, a compare and an OR on a cache-hot brick.
// - Boxed, where the CPU has AVX-512: the rays are queued, and when the scan is read back the bricks of the
//   box around all of them are laid out densely, a brick's index following from its key by arithmetic,
//   and the queued rays are traversed eight at a time, one per vector lane (cell_marks_wide.cpp). A ray's
//   next cell follows from its last through comparisons whose outcome a branch predictor cannot learn;
//   eight independent rays in the lanes of one vector keep the CPU busy where one ray waits on each step.
//   A scan whose box would exceed the budget (long rays at a fine resolution) falls back to the hashed way.
// Buffers are reused from scan to scan: no allocation in steady state.
#pragma once

#include <ogf/core/cell_key.hpp>
#include <ogf/core/huge_pages.hpp>
#include <ogf/core/measurement.hpp>
#include <ogf/fusion/ray_caster.hpp>

#include <algorithm>
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

// A scan's measurements: a 0.1 m street scan's are 13 MB, in huge pages where the kernel has them.
using MeasurementBuffer = std::vector<Measurement, HugePageAllocator<Measurement>>;

class CellMarks {
 public:
  // Bricks the dense box may hold: 128 bytes each, so 64 MB (a 30 m street scan needs about 75 k at 0.1 m
  // and 290 k, 37 MB, at 0.05 m, where the box halves the 50 ms the hashed bricks take).
  static constexpr std::size_t kMaxBoxBricks = std::size_t{1} << 19;

  // Boxed where the CPU has AVX-512, hashed otherwise.
  CellMarks();
  // wide false: always hashed (for tests comparing the two); maxBoxBricks: the box's budget.
  explicit CellMarks(bool wide, std::size_t maxBoxBricks = kMaxBoxBricks);

  void clear();

  void markFree(const CellKey& k);
  void markOccupied(const CellKey& k);
  // Marks every cell of the ray free (the same cells as iterating `ray`): the hot loop of a scan. Boxed,
  // the ray's traversal state is queued; hashed, it is traversed now, on local copies of the iterator's
  // state so nothing is spilled to memory, collecting the cells of one brick word (one local x) in a
  // register and storing it when x steps or the ray leaves the brick (a store per cell would chain each
  // mark to the last through memory).
  void markFree(const RayCaster& ray);

  // Appends one measurement per marked cell to `out`, in BrickOrder; occupied where both were marked.
  // Ends the scan: clear() comes before the next one's marks.
  void appendSorted(MeasurementBuffer& out);

  // Whether the last appendSorted used the dense box (for tests and benchmarks).
  bool lastScanBoxed() const { return last_boxed_; }
  // Whether this CPU can use the dense box (it has AVX-512).
  static bool boxAvailable();

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

  // The dense box: bricks [lo, lo + size) in brick coordinates, brick (x, y, z) at index
  // ((x − lo.x)·size.y + y − lo.y)·size.z + z − lo.z, which is BrickOrder; per brick 16 words, the free
  // words then the occupied ones. All zero between scans; one brick more at the end takes the marks of
  // inactive lanes (zero bits).
  struct Box {
    CellKey lo{};
    CellKey size{};
    std::vector<std::uint64_t, HugePageAllocator<std::uint64_t>> words;
  };
  static constexpr std::size_t kBoxWordsPerBrick = 16;

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
  // The hashed traversal of one ray.
  void markFreeHashed(const RayIterator& it);
  // The queued marks into the hashed bricks (a box over budget).
  void markQueuedHashed();
  // Widens the scan's bounding box (cells) to hold k.
  void cover(const CellKey& k) {
    lo_ = {std::min(lo_.x, k.x), std::min(lo_.y, k.y), std::min(lo_.z, k.z)};
    hi_ = {std::max(hi_.x, k.x), std::max(hi_.y, k.y), std::max(hi_.z, k.z)};
  }
  // Lays the box out for the scan's bounding box; false when it would exceed the budget.
  bool layOutBox();
  // The queued marks into the box; the free rays eight at a time (cell_marks_wide.cpp).
  void markQueuedBoxed();
  void markQueuedAvx512();
  // Appends the box's marks in BrickOrder and zeroes them.
  void appendBoxed(MeasurementBuffer& out);
  // Appends the marks of one brick (key: cell >> 3) in CellKey order: a word per local x, in it bit
  // 8·(local y) + local z; occupied where both are set.
  void appendBrick(const CellKey& key, const std::uint64_t* free, const std::uint64_t* occupied,
                   MeasurementBuffer& out);
  void clearQueues();

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

  bool wide_ = false;
  std::size_t max_box_bricks_ = kMaxBoxBricks;
  bool last_boxed_ = false;

  // Hashed.
  std::vector<Brick> bricks_;  // [0, used_) in use this scan; the rest kept for reuse
  std::size_t used_ = 0;
  std::vector<Slot> table_;    // power-of-two size, at most half full
  static constexpr unsigned kRecentBits = 9;
  std::array<Slot, std::size_t{1} << kRecentBits> recent_{};  // direct-mapped cache in front of table_
  CellKey last_cell_ = kNoCell;  // a cell of the brick of the last mark, and where that brick is
  Brick* last_brick_ = nullptr;
  std::vector<std::uint32_t> order_;  // scratch for appendSorted
  std::array<Measurement, 512> brick_cells_{};  // scratch for appendBrick

  // Boxed: the scan's marks until appendSorted, and the bounding box of their cells.
  std::vector<RayIterator> rays_;  // the queued rays' traversal states, each at its first cell
  std::vector<CellKey> free_cells_;
  std::vector<CellKey> occupied_cells_;
  CellKey lo_{};
  CellKey hi_{};
  Box box_;
};

}  // namespace ogf::fusion
