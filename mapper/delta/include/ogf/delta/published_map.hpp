// The map as the delta stream describes it. ogf-mapper keeps one (the state it has published) and every
// client rebuilds one; the two are equal exactly when their checksums are, which is how a client proves it
// missed nothing.
//
// A long drive publishes tens of millions of cells, so the cells live packed in hashed 8 × 8 × 1 slabs
// (PublishedBlock): about 8 bytes per cell where slabs are full, against some 60 for a hash-map node per
// cell.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/delta/published_block.hpp"
#include "ogf/delta/published_cell.hpp"
#include "ogf/delta/slab_table.hpp"

namespace ogf::delta {

class PublishedMap {
 public:
  // Sets (or adds) a cell.
  void set(const PublishedCell& cell);
  // Sets the cell when a client would see it differ from what is published (PublishedCell::visiblyDiffers;
  // a cell never published reads as the prior); returns whether it did. One lookup where find() and set()
  // take two.
  bool setIfVisiblyDiffers(const PublishedCell& cell) {
    return setIf(cell, [&](const PublishedCell& published, bool) { return cell.visiblyDiffers(published); });
  }
  // Sets the cell when decide(published cell or the prior, whether it was published) says so; returns
  // whether it did. With a decide that returns false, a look-up: DeltaStream::update's per-cell test.
  template <class Decide>
  bool setIf(const PublishedCell& cell, Decide decide);
  // A hint that the cell's slab is wanted soon (DeltaStream::update asks a few slabs ahead): nothing is read.
  void prefetch(const CellKey& key) const { blocks_.prefetch(PublishedBlock::blockKeyOf(key)); }
  // The cell, or nullopt when it was never published. A copy: cells are stored packed, not as
  // PublishedCell objects.
  std::optional<PublishedCell> find(const CellKey& key) const;
  void clear();
  // Cells published, those held elsewhere included.
  std::size_t size() const { return size_; }

  // Paging (persistence/map_pager.hpp). The cells of the box [lo, hi) (cell keys; x and y multiples of 8)
  // as cellsIn() lists them in slab order, leave memory by evict() but still count in size() and
  // checksum(), as cells held elsewhere; restore() puts such cells back, and forget() drops held cells
  // that will not come back (a lost page), with the count and checksum term evict() returned for them.
  struct Held {
    std::size_t cells = 0;
    std::uint64_t checksum = 0;  // wrapping sum of cellChecksum
  };
  std::vector<PublishedCell> cellsIn(const CellKey& lo, const CellKey& hi) const;
  Held evict(const CellKey& lo, const CellKey& hi);
  void restore(std::span<const PublishedCell> cells);
  void forget(const Held& held);
  // Counts cells held elsewhere that never were in memory here (a restart's pages, with the count and
  // checksum term of their cells): restore() and forget() then take them as if evict() had returned them.
  void hold(const Held& held);
  // The cells held elsewhere.
  Held held() const { return held_; }

  // Order-independent checksum of every cell (the wrapping sum of a 64-bit hash of key, probability,
  // class and the variance's bits), kept up to date in O(1) per change. 0 for an empty map.
  std::uint64_t checksum() const { return checksum_; }

  // Every cell in memory in CellKey order (deterministic; for keyframes and exports).
  std::vector<PublishedCell> sortedCells() const;

  // Bytes the storage holds: the cells' packed storage and the slab table's slots. Counts what is asked of
  // the allocator, not its own headers and rounding.
  std::size_t memoryBytes() const;

 private:
  // Stores the cell in its slab and keeps size, storage and checksum up to date.
  void put(PublishedBlock& block, const PublishedCell& cell);
  // setIf's store into the slab of the last look-up (last_, null when absent) at the cell's rank.
  void putAt(const PublishedCell& cell, bool present, std::size_t rank, const PublishedValue& old);
  // Calls visit(slab key, slab) for every slab in the box [lo, hi) of evict().
  template <class Visit>
  void forEachSlabIn(const CellKey& lo, const CellKey& hi, Visit visit) const;

  SlabTable blocks_;
  std::size_t size_ = 0;
  std::size_t stored_ = 0;  // cells the slabs have room for (their capacities), for memoryBytes() in O(1)
  std::uint64_t checksum_ = 0;
  Held held_;
  // setIfVisiblyDiffers' last slab (null: look it up); reset whenever slabs may move (SlabTable).
  PublishedBlock* last_ = nullptr;
  CellKey lastKey_{};
};

// The hash one cell contributes to PublishedMap::checksum().
std::uint64_t cellChecksum(const PublishedCell& cell);

template <class Decide>
bool PublishedMap::setIf(const PublishedCell& cell, Decide decide) {
  const CellKey blockKey = PublishedBlock::blockKeyOf(cell.key);
  // Candidates come in runs of one slab (the filter reports a block's cells in position order, x fastest):
  // the slab of the last one is checked before the table.
  if (last_ == nullptr || !(lastKey_ == blockKey)) {
    last_ = blocks_.find(blockKey);
    lastKey_ = blockKey;
  }
  const unsigned local = PublishedBlock::localIndexOf(cell.key);
  const bool present = last_ != nullptr && last_->has(local);
  const std::size_t rank = last_ != nullptr ? last_->rank(local) : 0;
  const PublishedValue old = present ? last_->valueAt(rank) : PublishedValue{};
  if (!decide(PublishedCell{cell.key, old.probability, old.cell_class, old.variance}, present)) return false;
  putAt(cell, present, rank, old);
  return true;
}

}  // namespace ogf::delta
