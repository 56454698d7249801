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

Block& BlockStorage::obtain(const CellKey& blockKey, bool& fresh) {
  Block& block = blocks_.findOrInsert(
      blockKey, [&] { return std::make_unique<Block>(cellsPerBlock_, floatsPerBlock_); }, fresh);
  block.changed();  // handed out for writing
  return block;
}

std::vector<CellKey> BlockStorage::sortedKeys() const {
  std::vector<CellKey> keys;
  keys.reserve(blocks_.size());
  blocks_.forEach([&](const CellKey& key, const Block&) { keys.push_back(key); });
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::size_t BlockStorage::memoryBytes() const {
  // Per block: the float arrays and marks and the Block object; plus the table's slots (key and pointer).
  const std::size_t perBlock = floatsPerBlock_ * sizeof(float) + cellsPerBlock_ + sizeof(Block);
  return blocks_.size() * perBlock + blocks_.capacity() * BlockTable<Block>::bytesPerSlot();
}

}  // namespace ogf::filter
