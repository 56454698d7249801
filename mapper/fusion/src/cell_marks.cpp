// CellMarks: brick lookup and the read-back in BrickOrder.
#include <ogf/fusion/cell_marks.hpp>

#include <algorithm>
#include <bit>

namespace ogf::fusion {

void CellMarks::clear() {
  used_ = 0;
  last_cell_ = kNoCell;
  last_brick_ = nullptr;
  std::fill(table_.begin(), table_.end(), Slot{});
  recent_.fill(Slot{});
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

void CellMarks::markFree(const RayCaster& ray) {
  // The traversal of RayIterator::step, unrolled per axis: same comparisons, same tie rule, same cells.
  const RayIterator& it = ray.begin();
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

void CellMarks::appendSorted(std::vector<Measurement>& out) {
  order_.resize(used_);
  for (std::size_t i = 0; i < used_; ++i) order_[i] = static_cast<std::uint32_t>(i);
  std::sort(order_.begin(), order_.end(),
            [this](std::uint32_t l, std::uint32_t r) { return bricks_[l].key < bricks_[r].key; });

  // Each brick's cells in CellKey order: a word per local x, in it bit 8·(local y) + local z.
  for (const std::uint32_t b : order_) {
    const Brick& brick = bricks_[b];
    const CellKey base{brick.key.x * 8, brick.key.y * 8, brick.key.z * 8};
    for (std::size_t lx = 0; lx < 8; ++lx) {
      const std::uint64_t occupied = brick.occupied[lx];
      for (std::uint64_t rest = brick.free[lx] | occupied; rest != 0; rest &= rest - 1) {
        const int bit = std::countr_zero(rest);
        out.push_back(
            {CellKey{base.x + static_cast<std::int32_t>(lx), base.y + (bit >> 3), base.z + (bit & 7)},
             ((occupied >> bit) & 1U) != 0U ? Measurement::kOccupied : Measurement::kFree});
      }
    }
  }
}

}  // namespace ogf::fusion
