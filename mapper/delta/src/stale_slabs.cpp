#include "ogf/delta/stale_slabs.hpp"

#include "ogf/delta/published_block.hpp"

namespace ogf::delta {

void StaleSlabs::markCellsSlab(const CellKey& cell) {
  const CellKey slab = PublishedBlock::blockKeyOf(cell);
  if (has_last_ && slab == last_) return;
  bool inserted = false;
  slabs_.obtain(slab, inserted);
  if (inserted) order_.push_back(slab);
  last_ = slab;
  has_last_ = true;
}

std::size_t StaleSlabs::take(std::size_t max, std::vector<CellKey>& out) {
  std::size_t taken = 0;
  while (taken < max && !order_.empty()) {
    out.push_back(order_.front());
    slabs_.erase(order_.front());
    order_.pop_front();
    ++taken;
  }
  has_last_ = false;
  return taken;
}

void StaleSlabs::clear() {
  slabs_.clear();
  order_.clear();
  has_last_ = false;
}

}  // namespace ogf::delta
