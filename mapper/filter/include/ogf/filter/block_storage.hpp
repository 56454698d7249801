// Hashed blocks of cells allocated on demand (docs/filter.md §6.3): a block is B×B×B cells in 3-D (B×B×1 in
// 2-D), each cell stored contiguously as floats (mean, variance, then one covariance per forward stencil
// slot), so a measurement touches about one cache line per stencil cell in at most 8 neighbouring blocks.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "ogf/filter/block_arena.hpp"
#include "ogf/filter/block_table.hpp"
#include "ogf/filter/filter_config.hpp"

namespace ogf::filter {

// Block containing a cell, and the cell's index inside it (x fastest, then y, then z).
inline CellKey blockKeyOf(const CellKey& cell) {
  // C++20 defines >> on negative integers as an arithmetic shift: floor division by 8.
  static_assert(kBlockSide == 8);
  return {cell.x >> 3, cell.y >> 3, cell.z >> 3};
}
inline std::size_t localIndexOf(const CellKey& cell) {
  return static_cast<std::size_t>((cell.x & 7) + 8 * ((cell.y & 7) + 8 * (cell.z & 7)));
}

class Block {
 public:
  // `floats` values (the layout is the filter's) in a slot of `arena` (of at least floats + cells bytes,
  // returned when the block goes), left uninitialised: the owner writes every one (the prior, or a
  // restored block). The marks start at 0.
  Block(std::size_t cells, std::size_t floats, BlockArena& arena);
  // As above, but the marks are left as the slot holds them too: the owner clears them (clearMarks) with
  // the values, before anyone reads the block.
  struct Unwritten {};
  Block(std::size_t cells, std::size_t floats, BlockArena& arena, Unwritten);
  void clearMarks() { std::fill(marks().begin(), marks().end(), std::uint8_t{0}); }
  std::size_t cells() const { return cells_; }
  // Banded layout: cell-major; cell l at l·(2 + F): [mean, variance, slot 0, ..., slot F-1]. Compact
  // layout: the cells' means, then their variance codes (variance_code.hpp) two to a float.
  float* data() { return data_.get(); }
  const float* data() const { return data_.get(); }
  std::span<float> values() { return {data_.get(), size_}; }
  std::span<const float> values() const { return {data_.get(), size_}; }
  // One byte per cell, kept after the values in the same allocation: the cell's measurement history as
  // the occupied priority needs it (CellMark).
  std::span<std::uint8_t> marks() { return {reinterpret_cast<std::uint8_t*>(data_.get() + size_), cells_}; }
  std::span<const std::uint8_t> marks() const {
    return {reinterpret_cast<const std::uint8_t*>(data_.get() + size_), cells_};
  }
  // The block's hash for the map checksum, kept until the block may have changed: whoever hands out its
  // data for writing calls changed(), so a checksum rehashes only the blocks written since the last one.
  void changed() { hashKnown_ = false; }
  bool hashKnown() const { return hashKnown_; }
  std::uint64_t hash() const { return hash_; }
  void setHash(std::uint64_t h) const {
    hash_ = h;
    hashKnown_ = true;
  }

 private:
  std::size_t cells_;
  std::size_t size_;
  struct Release {
    BlockArena* arena = nullptr;
    void operator()(float* values) const noexcept { arena->release(values); }
  };
  std::unique_ptr<float[], Release> data_;
  mutable std::uint64_t hash_ = 0;
  mutable bool hashKnown_ = false;
};

// A cell's mark: bit 7 set once an occupied measurement reached the cell, cleared when free measurements
// release it; bits 0-6 count the free measurements since the last occupied one (saturating).
struct CellMark {
  static constexpr std::uint8_t kHit = 0x80;
  static constexpr std::uint8_t kCount = 0x7F;
};

class BlockStorage {
 public:
  BlockStorage(int dimensions, std::size_t floatsPerBlock);
  BlockStorage(BlockStorage&&) noexcept = default;
  // The blocks go before their arena: member by member, the arena would go first.
  BlockStorage& operator=(BlockStorage&& other) noexcept {
    blocks_ = std::move(other.blocks_);
    arena_ = std::move(other.arena_);
    dimensions_ = other.dimensions_;
    cellsPerBlock_ = other.cellsPerBlock_;
    floatsPerBlock_ = other.floatsPerBlock_;
    return *this;
  }
  BlockStorage(const BlockStorage&) = delete;
  BlockStorage& operator=(const BlockStorage&) = delete;
  ~BlockStorage() = default;

  std::size_t cellsPerBlock() const { return cellsPerBlock_; }
  std::size_t floatsPerBlock() const { return floatsPerBlock_; }
  Block* find(const CellKey& blockKey) { return blocks_.find(blockKey); }
  const Block* find(const CellKey& blockKey) const { return blocks_.find(blockKey); }
  // A hint that `blockKey` is looked up soon (its slot in the table).
  void prefetch(const CellKey& blockKey) const { blocks_.prefetch(blockKey); }
  // The block, allocated (and `fresh` set) when missing. Not thread-safe.
  Block& obtain(const CellKey& blockKey, bool& fresh);
  // As obtain, but a fresh block is left unwritten (Block::Unwritten): its values and marks are the
  // caller's to write, before anything reads the block. Not thread-safe.
  Block& obtainUnwritten(const CellKey& blockKey, bool& fresh);
  std::size_t size() const { return blocks_.size(); }
  // Keys of all blocks, sorted: the deterministic order of iteration and files.
  std::vector<CellKey> sortedKeys() const;
  // Every block in the table's order (not deterministic: for order-independent sums and for selections).
  template <class Visit>
  void forEachBlock(Visit visit) const {
    blocks_.forEach(visit);
  }
  // Removes a block; false when there is none.
  bool erase(const CellKey& blockKey) { return blocks_.erase(blockKey); }
  // Bytes in use: the blocks' slots, their headers and the hash table. Not counted: the slots the arena
  // keeps for reuse (of erased blocks, and the rest of its last chunk, at most 2 MB).
  std::size_t memoryBytes() const;
  // Key of the cell at `local` in block `blockKey` (inline: the change detection calls it for every cell
  // it reports).
  CellKey cellKey(const CellKey& blockKey, std::size_t local) const {
    const auto l = static_cast<std::int32_t>(local);
    const std::int32_t z = dimensions_ == 3 ? blockKey.z * kBlockSide + l / (kBlockSide * kBlockSide) : 0;
    return {blockKey.x * kBlockSide + l % kBlockSide, blockKey.y * kBlockSide + (l / kBlockSide) % kBlockSide,
            z};
  }

 private:
  int dimensions_;
  std::size_t cellsPerBlock_;
  std::size_t floatsPerBlock_;
  std::unique_ptr<BlockArena> arena_;  // before blocks_: it outlives them, and stays put when moved
  BlockTable<Block> blocks_;
};

}  // namespace ogf::filter
