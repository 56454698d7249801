// Block allocation and bookkeeping.
#include "ogf/filter/block_storage.hpp"

#include <algorithm>

namespace ogf::filter {

Block::Block(std::size_t cells, std::size_t floats, BlockArena& arena) : Block(cells, floats, arena, Unwritten{}) {
  clearMarks();
}

Block::Block(std::size_t cells, std::size_t floats, BlockArena& arena, Unwritten)
    : cells_(cells), size_(floats), data_(static_cast<float*>(arena.allocate()), Release{&arena}) {}

BlockStorage::BlockStorage(int dimensions, std::size_t floatsPerBlock)
    : dimensions_(dimensions),
      cellsPerBlock_(dimensions == 3 ? kBlockSide * kBlockSide * kBlockSide : kBlockSide * kBlockSide),
      floatsPerBlock_(floatsPerBlock),
      arena_(std::make_unique<BlockArena>(floatsPerBlock * sizeof(float) + cellsPerBlock_)) {}

Block& BlockStorage::obtain(const CellKey& blockKey, bool& fresh) {
  Block& block = obtainUnwritten(blockKey, fresh);
  if (fresh) block.clearMarks();
  return block;
}

Block& BlockStorage::obtainUnwritten(const CellKey& blockKey, bool& fresh) {
  Block& block = blocks_.findOrInsert(
      blockKey, [&] { return std::make_unique<Block>(cellsPerBlock_, floatsPerBlock_, *arena_, Block::Unwritten{}); },
      fresh);
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
  // Per block its slot (values and marks) and Block object; plus the table's slots (key and pointer).
  const std::size_t slot = arena_ ? arena_->slotBytes() : 0;  // no arena: moved from
  return blocks_.size() * (slot + sizeof(Block)) +
         blocks_.capacity() * BlockTable<Block>::bytesPerSlot();
}

}  // namespace ogf::filter
