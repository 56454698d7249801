// The arena that holds block values: blocks are distinct, aligned and keep what is written to them across
// slabs and moves; the bytes in use count a full slab whole and a filling one by its blocks; blocks too large
// for a slab are allocated on their own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "ogf/filter/block_arena.hpp"

namespace ogf::filter {
namespace {

constexpr std::size_t kDefaultBlockFloats = 512 * 14;  // 8³ cells of the default stencil's 14 floats

void fill(float* block, std::size_t floats, std::size_t id) {
  for (std::size_t i = 0; i < floats; ++i) {
    block[i] = static_cast<float>(id * 7919 + i);
  }
}

bool holds(const float* block, std::size_t floats, std::size_t id) {
  for (std::size_t i = 0; i < floats; ++i) {
    if (block[i] != static_cast<float>(id * 7919 + i)) {
      return false;
    }
  }
  return true;
}

TEST(BlockArena, BlocksAreDistinctAlignedAndKeepTheirValuesAcrossSlabs) {
  BlockArena arena(kDefaultBlockFloats);
  std::vector<float*> blocks;
  for (std::size_t b = 0; b < 200; ++b) {  // 73 per slab: three slabs
    blocks.push_back(arena.allocate());
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(blocks.back()) % 64, 0U) << "block " << b;
    fill(blocks.back(), kDefaultBlockFloats, b);
  }
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    EXPECT_TRUE(holds(blocks[b], kDefaultBlockFloats, b)) << "block " << b;
  }
  std::vector<float*> sorted = blocks;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    EXPECT_GE(sorted[i] - sorted[i - 1], static_cast<std::ptrdiff_t>(kDefaultBlockFloats)) << "overlap";
  }
}

TEST(BlockArena, BytesInUseCountAFullSlabWholeAndAFillingOneByItsBlocks) {
  BlockArena arena(kDefaultBlockFloats);
  const std::size_t blockBytes = kDefaultBlockFloats * sizeof(float);  // 28 KiB, a multiple of 64
  const std::size_t perSlab = BlockArena::kSlabBytes / blockBytes;
  ASSERT_EQ(perSlab, 73U);
  EXPECT_EQ(arena.bytesInUse(), 0U);
  arena.allocate();
  EXPECT_EQ(arena.bytesInUse(), blockBytes);
  for (std::size_t b = 1; b < perSlab; ++b) {
    arena.allocate();
  }
  EXPECT_EQ(arena.bytesInUse(), BlockArena::kSlabBytes);
  arena.allocate();
  EXPECT_EQ(arena.bytesInUse(), BlockArena::kSlabBytes + blockBytes);
}

TEST(BlockArena, BlocksLargerThanASlabAreAllocatedOnTheirOwn) {
  const std::size_t floats = BlockArena::kSlabBytes / sizeof(float) + 1000;
  BlockArena arena(floats);
  float* a = arena.allocate();
  float* b = arena.allocate();
  fill(a, floats, 1);
  fill(b, floats, 2);
  EXPECT_TRUE(holds(a, floats, 1));
  EXPECT_TRUE(holds(b, floats, 2));
  const std::size_t rounded = (floats * sizeof(float) + 63) / 64 * 64;
  EXPECT_EQ(arena.bytesInUse(), 2 * rounded);
}

TEST(BlockArena, AMovedArenaKeepsItsBlocks) {
  BlockArena arena(kDefaultBlockFloats);
  std::vector<float*> blocks;
  for (std::size_t b = 0; b < 80; ++b) {
    blocks.push_back(arena.allocate());
    fill(blocks.back(), kDefaultBlockFloats, b);
  }
  const std::size_t bytes = arena.bytesInUse();
  BlockArena moved(std::move(arena));
  BlockArena assigned(16);
  assigned.allocate();
  assigned = std::move(moved);
  EXPECT_EQ(assigned.bytesInUse(), bytes);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    EXPECT_TRUE(holds(blocks[b], kDefaultBlockFloats, b)) << "block " << b;
  }
  // Allocation goes on in the last slab.
  float* next = assigned.allocate();
  fill(next, kDefaultBlockFloats, 999);
  EXPECT_TRUE(holds(blocks.back(), kDefaultBlockFloats, blocks.size() - 1));
  EXPECT_TRUE(holds(next, kDefaultBlockFloats, 999));
}

}  // namespace
}  // namespace ogf::filter
