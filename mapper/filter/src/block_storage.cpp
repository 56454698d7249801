// Block allocation and bookkeeping.
#include "ogf/filter/block_storage.hpp"

#include <algorithm>

namespace ogf::filter {

Block::Block(std::size_t cells, std::size_t floats)
    : cells_(cells), size_(floats),
      data_(std::make_unique_for_overwrite<float[]>(size_ + (cells + sizeof(float) - 1) / sizeof(float))) {
  std::fill(marks().begin(), marks().end(), std::uint8_t{0});
}

BlockStorage::BlockStorage(int dimensions, std::size_t floatsPerBlock)
    : dimensions_(dimensions),
      cellsPerBlock_(dimensions == 3 ? kBlockSide * kBlockSide * kBlockSide : kBlockSide * kBlockSide),
      floatsPerBlock_(floatsPerBlock) {}

Block* BlockStorage::find(const CellKey& blockKey) {
  const auto it = blocks_.find(blockKey);
  return it == blocks_.end() ? nullptr : it->second.get();
}

const Block* BlockStorage::find(const CellKey& blockKey) const {
  const auto it = blocks_.find(blockKey);
  return it == blocks_.end() ? nullptr : it->second.get();
}

Block& BlockStorage::obtain(const CellKey& blockKey, bool& fresh) {
  auto& slot = blocks_[blockKey];
  fresh = slot == nullptr;
  if (fresh) {
    slot = std::make_unique<Block>(cellsPerBlock_, floatsPerBlock_);
  }
  slot->changed();  // handed out for writing
  return *slot;
}

std::vector<CellKey> BlockStorage::sortedKeys() const {
  std::vector<CellKey> keys;
  keys.reserve(blocks_.size());
  for (const auto& [key, block] : blocks_) {
    keys.push_back(key);
  }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::size_t BlockStorage::memoryBytes() const {
  // Per block: the float arrays, the Block object, and an unordered_map node (key, pointer, next
  // pointer, cached hash); plus one bucket pointer per bucket.
  const std::size_t perBlock = floatsPerBlock_ * sizeof(float) + cellsPerBlock_ + sizeof(Block) +
                               sizeof(CellKey) + 3 * sizeof(void*) + sizeof(std::size_t);
  return blocks_.size() * perBlock + blocks_.bucket_count() * sizeof(void*);
}

}  // namespace ogf::filter
