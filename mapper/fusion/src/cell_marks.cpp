// CellMarks: the hashed bricks, the queue and the dense box, and the read-back in BrickOrder.
#include <ogf/fusion/cell_marks.hpp>

#include <algorithm>
#include <bit>

namespace ogf::fusion {
namespace {

constexpr std::int32_t kMin = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kMax = std::numeric_limits<std::int32_t>::max();

}  // namespace

bool CellMarks::boxAvailable() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __builtin_cpu_supports("avx512f");
#else
  return false;
#endif
}

CellMarks::CellMarks() : CellMarks(true) {}

CellMarks::CellMarks(bool wide, std::size_t maxBoxBricks)
    : wide_(wide && boxAvailable()), max_box_bricks_(maxBoxBricks) {
  clearQueues();
}

void CellMarks::clear() {
  clearQueues();
  used_ = 0;
  last_cell_ = kNoCell;
  last_brick_ = nullptr;
  std::fill(table_.begin(), table_.end(), Slot{});
  recent_.fill(Slot{});
}

void CellMarks::clearQueues() {
  rays_.clear();
  free_cells_.clear();
  occupied_cells_.clear();
  lo_ = {kMax, kMax, kMax};
  hi_ = {kMin, kMin, kMin};
}

void CellMarks::markFree(const CellKey& k) {
  if (!wide_) return mark(k, &Brick::free);
  free_cells_.push_back(k);
  cover(k);
}

void CellMarks::markOccupied(const CellKey& k) {
  if (!wide_) return mark(k, &Brick::occupied);
  occupied_cells_.push_back(k);
  cover(k);
}

void CellMarks::markFree(const RayCaster& ray) {
  const RayIterator& it = ray.begin();
  if (it.crossings_left_ == 0) return;
  if (!wide_) return markFreeHashed(it);
  rays_.push_back(it);
  // The traversal stays between its first cell and its end cell on every axis.
  cover(ray.originCell());
  cover(ray.endCell());
}

void CellMarks::markQueuedHashed() {
  for (const RayIterator& it : rays_) markFreeHashed(it);
  for (const CellKey& k : free_cells_) mark(k, &Brick::free);
  for (const CellKey& k : occupied_cells_) mark(k, &Brick::occupied);
}

bool CellMarks::layOutBox() {
  if (lo_.x > hi_.x) return false;  // nothing queued
  const CellKey lo{lo_.x >> 3, lo_.y >> 3, lo_.z >> 3};
  const std::array<std::int64_t, 3> size{std::int64_t{hi_.x >> 3} - lo.x + 1,
                                         std::int64_t{hi_.y >> 3} - lo.y + 1,
                                         std::int64_t{hi_.z >> 3} - lo.z + 1};
  const auto budget = static_cast<std::int64_t>(max_box_bricks_);
  // Each factor is checked before the product, which then cannot overflow.
  if (size[0] > budget || size[1] > budget || size[2] > budget || size[0] * size[1] > budget ||
      size[0] * size[1] * size[2] > budget) {
    return false;
  }
  box_.lo = lo;
  box_.size = {static_cast<std::int32_t>(size[0]), static_cast<std::int32_t>(size[1]),
               static_cast<std::int32_t>(size[2])};
  const auto words = static_cast<std::size_t>(size[0] * size[1] * size[2] + 1) * kBoxWordsPerBrick;
  if (box_.words.size() < words) box_.words.resize(words, 0);  // the words already there are zero
  return true;
}

void CellMarks::markQueuedBoxed() {
  const auto setBit = [this](const CellKey& k, std::size_t firstWord) {
    const auto brick =
        (static_cast<std::size_t>((k.x >> 3) - box_.lo.x) * static_cast<std::size_t>(box_.size.y) +
         static_cast<std::size_t>((k.y >> 3) - box_.lo.y)) *
            static_cast<std::size_t>(box_.size.z) +
        static_cast<std::size_t>((k.z >> 3) - box_.lo.z);
    box_.words[brick * kBoxWordsPerBrick + firstWord + static_cast<std::size_t>(k.x & 7)] |=
        std::uint64_t{1} << static_cast<unsigned>(((k.y & 7) << 3) | (k.z & 7));
  };
  for (const CellKey& k : free_cells_) setBit(k, 0);
  for (const CellKey& k : occupied_cells_) setBit(k, 8);
  markQueuedAvx512();
}

namespace {
// The cells marked in a brick of the box (its 8 free words, then its 8 occupied ones). Only the boxed way
// calls it, on CPUs with AVX-512, which all have POPCNT; without the target the count is a library call.
__attribute__((target("popcnt"))) std::size_t markedInBoxBrick(const std::uint64_t* words) {
  std::size_t marked = 0;
  for (std::size_t lx = 0; lx < 8; ++lx) {
    marked += static_cast<std::size_t>(__builtin_popcountll(words[lx] | words[lx + 8]));
  }
  return marked;
}
}  // namespace

void CellMarks::appendBoxed(MeasurementBuffer& out) {
  // First the marked bricks and their cells, so `out` grows once: grown by doubling, a first scan's
  // measurements (13 MB for a 0.1 m street scan) were copied and their pages faulted in several times.
  order_.clear();
  std::size_t cells = 0;
  const std::uint64_t* words = box_.words.data();
  const auto sizeY = static_cast<std::size_t>(box_.size.y);
  const auto sizeZ = static_cast<std::size_t>(box_.size.z);
  const std::size_t bricks = static_cast<std::size_t>(box_.size.x) * sizeY * sizeZ;
  for (std::size_t b = 0; b < bricks; ++b, words += kBoxWordsPerBrick) {
    const std::size_t marked = markedInBoxBrick(words);
    if (marked == 0) continue;
    order_.push_back(static_cast<std::uint32_t>(b));
    cells += marked;
  }
  out.reserve(out.size() + cells);
  for (const std::uint32_t b : order_) {
    std::uint64_t* brick = box_.words.data() + std::size_t{b} * kBoxWordsPerBrick;
    const auto bz = static_cast<std::int32_t>(b % sizeZ);
    const auto by = static_cast<std::int32_t>((b / sizeZ) % sizeY);
    const auto bx = static_cast<std::int32_t>(b / sizeZ / sizeY);
    appendBrick({box_.lo.x + bx, box_.lo.y + by, box_.lo.z + bz}, brick, brick + 8, out);
    std::fill(brick, brick + kBoxWordsPerBrick, std::uint64_t{0});
  }
}

void CellMarks::grow() {
  const std::size_t size = table_.empty() ? 1024 : table_.size() * 2;
  table_.assign(size, Slot{});
  const std::size_t mask = size - 1;
  for (std::size_t i = 0; i < used_; ++i) {
    std::size_t s = CellKeyHash{}(bricks_[i].key) & mask;
    while (table_[s].brick != kEmpty) s = (s + 1) & mask;
    table_[s] = {bricks_[i].key, static_cast<std::uint32_t>(i)};
  }
}

std::uint32_t CellMarks::brickIndex(std::int32_t bx, std::int32_t by, std::int32_t bz) {
  const CellKey b{bx, by, bz};
  // The rays of one firing cross the bricks the previous firing crossed: a small direct-mapped cache of
  // recent bricks, which stays in L1, answers most look-ups before the table (megabytes at 30 m) is read.
  const std::uint32_t h = static_cast<std::uint32_t>(bx) * 0x9E3779B1U ^ static_cast<std::uint32_t>(by) * 0x85EBCA77U ^
                          static_cast<std::uint32_t>(bz) * 0xC2B2AE3DU;
  Slot& recent = recent_[h >> (32U - kRecentBits)];
  if (recent.brick != kEmpty && recent.key == b) return recent.brick;
  recent = {b, tableIndex(b)};
  return recent.brick;
}

std::uint32_t CellMarks::tableIndex(CellKey b) {
  if ((used_ + 1) * 2 > table_.size()) grow();
  const std::size_t mask = table_.size() - 1;
  std::size_t s = CellKeyHash{}(b) & mask;
  while (table_[s].brick != kEmpty) {
    if (table_[s].key == b) return table_[s].brick;
    s = (s + 1) & mask;
  }
  if (used_ == bricks_.size()) bricks_.emplace_back();
  Brick& brick = bricks_[used_];
  brick.free.fill(0);
  brick.occupied.fill(0);
  brick.key = b;
  table_[s] = {b, static_cast<std::uint32_t>(used_)};
  return static_cast<std::uint32_t>(used_++);
}

void CellMarks::markFreeHashed(const RayIterator& it) {
  // The traversal of RayIterator::step, unrolled per axis: same comparisons, same tie rule, same cells.
  std::int64_t left = it.crossings_left_;
  if (left == 0) return;
  std::int32_t x = it.cell_[0], y = it.cell_[1], z = it.cell_[2];
  const std::int32_t sx = it.step_[0], sy = it.step_[1], sz = it.step_[2];
  double nx = it.next_[0], ny = it.next_[1], nz = it.next_[2];
  const double dx = it.delta_[0], dy = it.delta_[1], dz = it.delta_[2];
  std::int64_t lx = it.left_[0], ly = it.left_[1], lz = it.left_[2];
  // A step up enters a new brick at local coordinate 0, a step down at 7.
  const std::int32_t enter_x = sx > 0 ? 0 : 7, enter_y = sy > 0 ? 0 : 7, enter_z = sz > 0 ? 0 : 7;
  constexpr double kNever = RayIterator::kNever;

  CellKey base{x, y, z};  // a cell of `brick`
  Brick* brick = last_brick_;
  if (!sameBrick(base, last_cell_)) brick = brickAt(base);
  std::uint64_t word = 0;  // marks of the current local x, not yet stored
  const auto bit = [](std::int32_t cy, std::int32_t cz) {
    return std::uint64_t{1} << static_cast<unsigned>(((cy & 7) << 3) | (cz & 7));
  };
  const auto store = [&] { brick->free[static_cast<std::size_t>(x & 7)] |= word; };
  for (;;) {
    word |= bit(y, z);
    if (nx < ny && nx < nz) {
      store();
      word = 0;
      x += sx;
      nx = --lx == 0 ? kNever : nx + dx;
      if (--left == 0) break;
      if ((x & 7) == enter_x) {
        base = {x, y, z};
        brick = brickAt(base);
      }
    } else if (ny < nx && ny < nz) {
      y += sy;
      ny = --ly == 0 ? kNever : ny + dy;
      if (--left == 0) break;
      if ((y & 7) == enter_y) {
        store();
        word = 0;
        base = {x, y, z};
        brick = brickAt(base);
      }
    } else if (nz < nx && nz < ny) {
      z += sz;
      nz = --lz == 0 ? kNever : nz + dz;
      if (--left == 0) break;
      if ((z & 7) == enter_z) {
        store();
        word = 0;
        base = {x, y, z};
        brick = brickAt(base);
      }
    } else {
      // Tied crossings: RayIterator's tie rule, then the brick of wherever it lands.
      store();
      word = 0;
      const unsigned axes = RayIterator::tiedAxes(nx, ny, nz, sx, sy, sz);
      if ((axes & 1U) != 0) {
        x += sx;
        --left;
        nx = --lx == 0 ? kNever : nx + dx;
      }
      if ((axes & 2U) != 0) {
        y += sy;
        --left;
        ny = --ly == 0 ? kNever : ny + dy;
      }
      if ((axes & 4U) != 0) {
        z += sz;
        --left;
        nz = --lz == 0 ? kNever : nz + dz;
      }
      if (left == 0) break;
      const CellKey now{x, y, z};
      if (!sameBrick(now, base)) {
        base = now;
        brick = brickAt(base);
      }
    }
  }
  store();
  last_cell_ = base;
  last_brick_ = brick;
}

void CellMarks::appendSorted(MeasurementBuffer& out) {
  last_boxed_ = false;
  if (wide_) {
    if (layOutBox()) {
      markQueuedBoxed();
      appendBoxed(out);
      clearQueues();
      last_boxed_ = true;
      return;
    }
    markQueuedHashed();
    clearQueues();
  }
  order_.resize(used_);
  for (std::size_t i = 0; i < used_; ++i) order_[i] = static_cast<std::uint32_t>(i);
  std::sort(order_.begin(), order_.end(),
            [this](std::uint32_t l, std::uint32_t r) { return bricks_[l].key < bricks_[r].key; });

  std::size_t cells = 0;
  for (std::size_t i = 0; i < used_; ++i) {
    for (std::size_t lx = 0; lx < 8; ++lx) {
      cells += static_cast<std::size_t>(std::popcount(bricks_[i].free[lx] | bricks_[i].occupied[lx]));
    }
  }
  out.reserve(out.size() + cells);
  for (const std::uint32_t b : order_) {
    const Brick& brick = bricks_[b];
    appendBrick(brick.key, brick.free.data(), brick.occupied.data(), out);
  }
}

void CellMarks::appendBrick(const CellKey& key, const std::uint64_t* free, const std::uint64_t* occupied,
                            MeasurementBuffer& out) {
  // Into a local buffer, then one insert: out.push_back per cell stored and reloaded the vector's end on
  // every cell (a Measurement's int8 field may alias it).
  std::array<Measurement, 512>& cells = brick_cells_;
  std::size_t n = 0;
  const CellKey base{key.x * 8, key.y * 8, key.z * 8};
  for (std::size_t lx = 0; lx < 8; ++lx) {
    for (std::uint64_t rest = free[lx] | occupied[lx]; rest != 0; rest &= rest - 1) {
      const int bit = std::countr_zero(rest);
      cells[n++] = {CellKey{base.x + static_cast<std::int32_t>(lx), base.y + (bit >> 3), base.z + (bit & 7)},
                    ((occupied[lx] >> bit) & 1U) != 0U ? Measurement::kOccupied : Measurement::kFree};
    }
  }
  out.insert(out.end(), cells.begin(), cells.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace ogf::fusion
