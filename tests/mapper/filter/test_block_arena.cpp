// BlockArena: slots that do not overlap, keep what is written to them through the small chunks and the
// huge-page ones, come back in the order they were released, and BlockStorage hands its blocks back before
// its arena goes (move assignment). HugePageAllocator: a vector keeps its contents as it grows from the
// ordinary heap into huge pages.
#include "ogf/filter/block_arena.hpp"

#include <ogf/core/huge_pages.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "ogf/filter/block_storage.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define OGF_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OGF_TEST_ASAN 1
#endif
#endif
#ifdef OGF_TEST_ASAN
#include <sanitizer/asan_interface.h>
#endif

namespace ogf::filter {
namespace {

TEST(BlockArena, SlotsAreCacheLineAlignedDisjointAndKeepTheirBytesPastTheHugePageChunks) {
  constexpr std::size_t kSlot = 3584;  // a compact 8³ block: 512 floats, 512 codes, 512 marks
  BlockArena arena(kSlot);
  ASSERT_EQ(arena.slotBytes(), kSlot);
  // 24 MB of slots: the 256 KB chunks and about eight 2 MB ones.
  const std::size_t count = (std::size_t{24} << 20) / kSlot;
  std::vector<unsigned char*> slots;
  for (std::size_t i = 0; i < count; ++i) {
    auto* slot = static_cast<unsigned char*>(arena.allocate());
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(slot) % 64, 0U) << "slot " << i;
    std::memset(slot, static_cast<int>(i % 251), kSlot);
    slots.push_back(slot);
  }
  EXPECT_GE(arena.mappedBytes(), count * kSlot);
  EXPECT_LE(arena.mappedBytes(), count * kSlot + (std::size_t{2} << 20));
  std::vector<unsigned char*> sorted = slots;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i) {
    ASSERT_GE(static_cast<std::size_t>(sorted[i] - sorted[i - 1]), kSlot) << "slots overlap";
  }
  for (std::size_t i = 0; i < count; ++i) {
    const auto want = static_cast<unsigned char>(i % 251);
    ASSERT_TRUE(std::all_of(slots[i], slots[i] + kSlot, [&](unsigned char b) { return b == want; }))
        << "slot " << i << " lost its bytes";
  }
}

TEST(BlockArena, ReleasedSlotsAreReusedLastReleasedFirstBeforeNewOnes) {
  BlockArena arena(100);
  EXPECT_EQ(arena.slotBytes(), 128U);
  void* a = arena.allocate();
  void* b = arena.allocate();
  void* c = arena.allocate();
  const std::size_t mapped = arena.mappedBytes();
  arena.release(a);
  arena.release(c);
  EXPECT_EQ(arena.allocate(), c);
  EXPECT_EQ(arena.allocate(), a);
  void* d = arena.allocate();
  EXPECT_NE(d, a);
  EXPECT_NE(d, b);
  EXPECT_NE(d, c);
  EXPECT_GE(arena.mappedBytes(), mapped);
}

// Under AddressSanitizer (OGF_SANITIZE=ON) a slot is usable only between allocate() and release(), so a
// block overrun or a write after release is reported as it would be with malloc.
TEST(BlockArena, OnlySlotsHandedOutAreAddressableUnderAddressSanitizer) {
#ifndef OGF_TEST_ASAN
  GTEST_SKIP() << "not an AddressSanitizer build (configure with -DOGF_SANITIZE=ON)";
#else
  constexpr std::size_t kSlot = 3584;
  BlockArena arena(kSlot);
  auto* a = static_cast<char*>(arena.allocate());
  auto* b = static_cast<char*>(arena.allocate());
  EXPECT_EQ(__asan_region_is_poisoned(a, kSlot), nullptr);
  EXPECT_EQ(__asan_region_is_poisoned(b, kSlot), nullptr);
  EXPECT_TRUE(__asan_address_is_poisoned(b + kSlot)) << "the chunk's rest, not handed out yet";
  arena.release(a);
  EXPECT_TRUE(__asan_address_is_poisoned(a));
  EXPECT_TRUE(__asan_address_is_poisoned(a + kSlot - 1));
  EXPECT_EQ(arena.allocate(), a);
  EXPECT_EQ(__asan_region_is_poisoned(a, kSlot), nullptr);
#endif
}

TEST(BlockStorage, MoveAssignmentGivesTheOldBlocksBackBeforeTheirArenaGoes) {
  constexpr std::size_t kFloats = 768;
  BlockStorage kept(3, kFloats);
  BlockStorage replaced(3, kFloats);
  bool fresh = false;
  for (int x = 0; x < 50; ++x) {
    kept.obtain({x, 0, 0}, fresh).values()[0] = static_cast<float>(x);
    replaced.obtain({x, 1, 0}, fresh).values()[0] = -1.0F;
  }
  replaced = std::move(kept);
  ASSERT_EQ(replaced.size(), 50U);
  EXPECT_EQ(replaced.find({7, 1, 0}), nullptr);
  ASSERT_NE(replaced.find({7, 0, 0}), nullptr);
  EXPECT_EQ(replaced.find({7, 0, 0})->values()[0], 7.0F);
  // The moved-in arena serves new blocks and takes erased ones back.
  Block& added = replaced.obtain({100, 0, 0}, fresh);
  EXPECT_TRUE(fresh);
  added.values()[0] = 1.0F;
  EXPECT_TRUE(replaced.erase({100, 0, 0}));
  EXPECT_EQ(replaced.size(), 50U);
}

TEST(HugePageAllocator, AVectorKeepsItsContentsGrowingIntoHugePagesAndBack) {
  std::vector<std::uint64_t, HugePageAllocator<std::uint64_t>> words;
  for (std::uint64_t i = 0; i < (std::uint64_t{1} << 20); ++i) words.push_back(i * 2654435761U);
  ASSERT_GE(words.capacity() * sizeof(std::uint64_t), kHugePageBytes);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(words.data()) % kHugePageBytes, 0U);
  for (std::uint64_t i = 0; i < words.size(); ++i) ASSERT_EQ(words[i], i * 2654435761U) << "word " << i;
  words.resize(1000);
  words.shrink_to_fit();
  EXPECT_LT(words.capacity() * sizeof(std::uint64_t), kHugePageBytes);
  for (std::uint64_t i = 0; i < words.size(); ++i) ASSERT_EQ(words[i], i * 2654435761U) << "word " << i;
}

}  // namespace
}  // namespace ogf::filter
