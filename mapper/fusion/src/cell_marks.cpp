// CellMarks: brick lookup and the read-back in CellKey order.
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

std::uint32_t CellMarks::brickIndex(CellKey b) {
  // The rays of one firing cross the bricks the previous firing crossed: a small direct-mapped cache of
  // recent bricks, which stays in L1, answers most look-ups before the table (megabytes at 30 m) is read.
  const std::uint32_t h = static_cast<std::uint32_t>(b.x) * 0x9E3779B1U ^ static_cast<std::uint32_t>(b.y) * 0x85EBCA77U ^
                          static_cast<std::uint32_t>(b.z) * 0xC2B2AE3DU;
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

void CellMarks::appendSorted(std::vector<Measurement>& out) {
  order_.resize(used_);
  for (std::size_t i = 0; i < used_; ++i) order_[i] = static_cast<std::uint32_t>(i);
  std::sort(order_.begin(), order_.end(),
            [this](std::uint32_t l, std::uint32_t r) { return bricks_[l].key < bricks_[r].key; });

  // Lexicographic (x, y, z) order across bricks sorted by (bx, by, bz): for each brick column x, each local
  // x; then for each brick row y within it, each local y; then the bricks of that row in z order.
  std::size_t x_begin = 0;
  while (x_begin < order_.size()) {
    const std::int32_t bx = bricks_[order_[x_begin]].key.x;
    std::size_t x_end = x_begin;
    while (x_end < order_.size() && bricks_[order_[x_end]].key.x == bx) ++x_end;
    for (std::int32_t lx = 0; lx < 8; ++lx) {
      std::size_t y_begin = x_begin;
      while (y_begin < x_end) {
        const std::int32_t by = bricks_[order_[y_begin]].key.y;
        std::size_t y_end = y_begin;
        while (y_end < x_end && bricks_[order_[y_end]].key.y == by) ++y_end;
        for (std::int32_t ly = 0; ly < 8; ++ly) {
          const auto shift = static_cast<unsigned>(ly * 8);
          for (std::size_t i = y_begin; i < y_end; ++i) {
            const Brick& brick = bricks_[order_[i]];
            const auto w = static_cast<std::size_t>(lx);
            const auto occupied = static_cast<unsigned>((brick.occupied[w] >> shift) & 0xFFU);
            const auto any = static_cast<unsigned>(((brick.free[w] | brick.occupied[w]) >> shift) & 0xFFU);
            if (any == 0U) continue;
            // Only the set bits, lowest z first.
            for (unsigned rest = any; rest != 0U; rest &= rest - 1U) {
              const int lz = std::countr_zero(rest);
              out.push_back({CellKey{bx * 8 + lx, by * 8 + ly, brick.key.z * 8 + lz},
                             ((occupied >> lz) & 1U) != 0U ? Measurement::kOccupied : Measurement::kFree});
            }
          }
        }
        y_begin = y_end;
      }
    }
    x_begin = x_end;
  }
}

}  // namespace ogf::fusion
