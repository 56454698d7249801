// Slabs (PublishedBlock's 8 × 8 × 1) holding a cell whose change was worth sending but found the waiting
// set full (DeferredCells at its capacity): the change is not kept, its slab is. Once the waiting set has
// room again, the caller reads those slabs' cells from the map as they are then, oldest slab first, and
// they are judged against the published map like any change (DeltaStream::refreshStale), so a client
// still ends with every cell within the publishing rule of the map, however far the map's changes
// outran the budget. A slab costs one entry however many of its cells overflowed.
#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include "ogf/core/cell_key.hpp"
#include "ogf/core/cell_key_table.hpp"

namespace ogf::delta {

class StaleSlabs {
 public:
  bool empty() const { return slabs_.size() == 0; }
  std::size_t size() const { return slabs_.size(); }

  // Marks the slab of `cell` (once: a marked slab keeps its place).
  void markCellsSlab(const CellKey& cell);
  // Moves up to `max` slab keys, oldest first, into `out` (appended); returns how many.
  std::size_t take(std::size_t max, std::vector<CellKey>& out);
  void clear();

 private:
  struct Marked {};
  CellKeyTable<Marked, 1, 2> slabs_;
  std::deque<CellKey> order_;
  // The slab marked last: an overflowing scan marks the cells of one slab in a row.
  CellKey last_{};
  bool has_last_ = false;
};

}  // namespace ogf::delta
