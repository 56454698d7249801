// PublishedMap's packed slab storage keeps the semantics of a plain map of cells: what was set is found,
// an overwrite replaces, the checksum is the wrapping sum of cellChecksum over the cells (the value clients
// verify against the mapper's), sortedCells is in CellKey order, and the storage costs what it states.
#include <gtest/gtest.h>

#include <bit>
#include <iostream>
#include <map>
#include <random>
#include <vector>

#include "ogf/delta/published_map.hpp"

namespace {

using ogf::CellKey;
using namespace ogf::delta;

bool sameCell(const PublishedCell& a, const PublishedCell& b) {
  return a.key == b.key && a.probability == b.probability && a.cell_class == b.cell_class &&
         std::bit_cast<std::uint32_t>(a.variance) == std::bit_cast<std::uint32_t>(b.variance);
}

// The straightforward map the packed one must agree with.
struct Reference {
  std::map<CellKey, PublishedCell> cells;
  void set(const PublishedCell& c) { cells[c.key] = c; }
  std::uint64_t checksum() const {
    std::uint64_t sum = 0;
    for (const auto& [key, c] : cells) sum += cellChecksum(c);
    return sum;
  }
};

void expectAgrees(const PublishedMap& map, const Reference& ref) {
  ASSERT_EQ(map.size(), ref.cells.size());
  EXPECT_EQ(map.checksum(), ref.checksum());
  const auto sorted = map.sortedCells();
  ASSERT_EQ(sorted.size(), ref.cells.size());
  auto it = ref.cells.begin();
  for (std::size_t i = 0; i < sorted.size(); ++i, ++it) {
    ASSERT_TRUE(sameCell(sorted[i], it->second)) << "cell " << i << " at " << it->first.x << "," << it->first.y
                                                 << "," << it->first.z;
    const auto found = map.find(it->first);
    ASSERT_TRUE(found.has_value());
    ASSERT_TRUE(sameCell(*found, it->second));
  }
}

TEST(PublishedMap, FindsWhatWasSetAcrossSlabEdgesAndZero) {
  PublishedMap map;
  Reference ref;
  // Every cell of a 2-D square and a 3-D box that straddle 0 and several slab edges, each probability its own.
  std::int16_t p = 0;
  for (int x = -17; x <= 9; x += 2)
    for (int y = -10; y <= 16; y += 3) {
      const PublishedCell flat{{x, y, 0}, ++p, static_cast<std::int8_t>(p % 3 - 1), 0.5f * p};
      map.set(flat);
      ref.set(flat);
      for (int z = -3; z <= 2; ++z) {
        const PublishedCell c{{x + 1, y, z}, ++p, 1, -0.25f * p};
        map.set(c);
        ref.set(c);
      }
    }
  expectAgrees(map, ref);
  // Neighbours never set read as absent, also in slabs that hold other cells.
  EXPECT_FALSE(map.find({-17, -10, 1}).has_value());  // above a 2-D cell, beside a 3-D column
  EXPECT_FALSE(map.find({-17, -9, 0}).has_value());
  EXPECT_FALSE(map.find({-16, -10, 3}).has_value());  // above a 3-D column
  EXPECT_FALSE(map.find({1000, -1000, 0}).has_value());
}

TEST(PublishedMap, OverwriteReplacesTheCellAndItsChecksum) {
  PublishedMap map;
  const PublishedCell first{{-1, -8, 0}, 9000, 1, 0.25f};
  const PublishedCell second{{-1, -8, 0}, 1000, -1, 0.75f};
  map.set(first);
  const std::uint64_t one = map.checksum();
  EXPECT_EQ(one, cellChecksum(first));
  map.set(second);
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(map.checksum(), cellChecksum(second));
  ASSERT_TRUE(map.find(first.key).has_value());
  EXPECT_TRUE(sameCell(*map.find(first.key), second));
  map.set(first);
  EXPECT_EQ(map.checksum(), one);
}

TEST(PublishedMap, SetIfVisiblyDiffersSetsOnlyWhatAClientWouldSee) {
  PublishedMap map;
  const std::size_t empty = map.memoryBytes();
  // The prior, on a cell never published: nothing to publish, and no slab allocated for it.
  EXPECT_FALSE(map.setIfVisiblyDiffers({{-3, 4, 1}, kPriorProbability, 0, 0.7f}));
  EXPECT_EQ(map.size(), 0u);
  EXPECT_EQ(map.memoryBytes(), empty);
  EXPECT_TRUE(map.setIfVisiblyDiffers({{-3, 4, 1}, 8000, 1, 0.7f}));
  // The same probability and class with another variance is no news and leaves the stored variance.
  EXPECT_FALSE(map.setIfVisiblyDiffers({{-3, 4, 1}, 8000, 1, 0.1f}));
  EXPECT_EQ(map.find({-3, 4, 1})->variance, 0.7f);
  EXPECT_TRUE(map.setIfVisiblyDiffers({{-3, 4, 1}, 8000, 0, 0.1f}));
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(map.checksum(), cellChecksum({{-3, 4, 1}, 8000, 0, 0.1f}));
}

// The checksum of a fixed set of cells, as the unordered_map storage computed it: clients compare the
// mapper's checksum with their own, so the value may not depend on how the map is stored.
TEST(PublishedMap, ChecksumOfAFixedMapIsUnchanged) {
  PublishedMap map;
  map.set({{0, 0, 0}, 7000, 1, 0.25f});
  map.set({{-1, -1, 0}, 1200, -1, 0.5f});
  map.set({{-8, 7, 0}, 5000, 0, -0.0f});
  map.set({{8, -9, 3}, 9999, 1, 1e-3f});
  map.set({{-123456, 654321, -42}, 0, -1, 2.5f});
  map.set({{0, 0, 0}, 6500, 1, 0.125f});
  EXPECT_EQ(map.size(), 5u);
  EXPECT_EQ(map.checksum(), 13172269629375715028ULL);
  const std::vector<CellKey> order{{-123456, 654321, -42}, {-8, 7, 0}, {-1, -1, 0}, {0, 0, 0}, {8, -9, 3}};
  const auto sorted = map.sortedCells();
  ASSERT_EQ(sorted.size(), order.size());
  for (std::size_t i = 0; i < order.size(); ++i) EXPECT_EQ(sorted[i].key, order[i]);
}

TEST(PublishedMap, RandomSetsAndOverwritesAgreeWithAPlainMap) {
  for (const int dimensions : {2, 3}) {
    std::mt19937 rng(static_cast<unsigned>(dimensions));
    std::uniform_int_distribution<int> coord(-40, 40), z(-5, 5), prob(0, kProbabilityScale), cls(-1, 1);
    std::uniform_real_distribution<float> var(0.0f, 2.0f);
    PublishedMap map;
    Reference ref;
    for (int round = 0; round < 5; ++round) {
      // Enough cells per round that most are overwritten by later rounds, and slabs fill in every order.
      for (int i = 0; i < 20000; ++i) {
        const PublishedCell c{{coord(rng), coord(rng), dimensions == 3 ? z(rng) : 0},
                              static_cast<std::int16_t>(prob(rng)), static_cast<std::int8_t>(cls(rng)), var(rng)};
        map.set(c);
        ref.set(c);
      }
      SCOPED_TRACE(testing::Message() << dimensions << "-D, round " << round);
      expectAgrees(map, ref);
    }
    map.clear();
    EXPECT_EQ(map.size(), 0u);
    EXPECT_EQ(map.checksum(), 0u);
    EXPECT_TRUE(map.sortedCells().empty());
  }
}

// Stated bounds: at most 8.5 bytes per cell where the slabs are full (7 bytes of cell, and the slab's table
// slots, 32 bytes each at 3/8 to 3/4 load, shared by 64 cells); at most 18 per cell where each slab holds one
// row of 8 (a wall crossing 8 × 8 × 1 slabs edge-on).
TEST(PublishedMap, MemoryPerCellIsWithinTheStatedBounds) {
  PublishedMap full;
  for (int x = -256; x < 256; ++x)
    for (int y = -256; y < 256; ++y) full.set({{x, y, 0}, 7000, 1, 0.5f});
  const double fullPerCell = static_cast<double>(full.memoryBytes()) / static_cast<double>(full.size());
  EXPECT_LE(fullPerCell, 8.5);
  EXPECT_GE(fullPerCell, 7.0);

  PublishedMap wall;
  for (int y = -512; y < 512; ++y)
    for (int z = -32; z < 32; ++z) wall.set({{3, y, z}, 7000, 1, 0.5f});
  const double wallPerCell = static_cast<double>(wall.memoryBytes()) / static_cast<double>(wall.size());
  EXPECT_LE(wallPerCell, 18.0);
  std::cout << "full slabs " << fullPerCell << " bytes per cell, one row per slab " << wallPerCell << "\n";
}

// Paging: the cells of a box leave memory but still count; back, the map is as it was; a box that will not
// come back is forgotten, and the map then equals one that never held those cells.
TEST(PublishedMap, EvictedCellsStillCountAndComeBackOrAreForgotten) {
  // The same random cells each time; `outside` gets those outside the box [0, 32)³.
  const auto fill = [](PublishedMap& map, PublishedMap* outside) {
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> coord(-40, 71);
    for (int i = 0; i < 3000; ++i) {
      const PublishedCell c{{coord(rng), coord(rng), coord(rng) % 40}, static_cast<std::int16_t>(rng() % 10001),
                            static_cast<std::int8_t>(static_cast<int>(rng() % 3) - 1),
                            static_cast<float>(rng() % 100) * 0.01f};
      map.set(c);
      const bool inBox = c.key.x >= 0 && c.key.x < 32 && c.key.y >= 0 && c.key.y < 32 && c.key.z >= 0 && c.key.z < 32;
      if (!inBox && outside != nullptr) outside->set(c);
    }
  };
  PublishedMap map;
  PublishedMap outside;
  fill(map, &outside);
  const auto all = map.sortedCells();
  const std::size_t size = map.size();
  const std::uint64_t checksum = map.checksum();
  const std::size_t memory = map.memoryBytes();
  const CellKey lo{0, 0, 0};
  const CellKey hi{32, 32, 32};
  const auto box = map.cellsIn(lo, hi);
  ASSERT_EQ(box.size(), size - outside.size());
  ASSERT_GT(box.size(), 100u);
  const PublishedMap::Held held = map.evict(lo, hi);
  EXPECT_EQ(held.cells, box.size());
  EXPECT_EQ(map.size(), size);
  EXPECT_EQ(map.checksum(), checksum);
  EXPECT_LT(map.memoryBytes(), memory);
  EXPECT_EQ(map.sortedCells().size(), outside.size());
  EXPECT_FALSE(map.find(box.front().key).has_value());
  EXPECT_TRUE(map.cellsIn(lo, hi).empty());

  map.restore(box);
  EXPECT_EQ(map.held().cells, 0u);
  EXPECT_EQ(map.size(), size);
  EXPECT_EQ(map.checksum(), checksum);
  const auto restored = map.sortedCells();
  ASSERT_EQ(restored.size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(restored[i].key, all[i].key);
    EXPECT_FALSE(restored[i].visiblyDiffers(all[i]));
  }

  // Published again while held: the newer cell stays, the held copy is dropped, nothing counts twice.
  map.evict(lo, hi);
  PublishedCell newer = box.front();
  newer.probability = static_cast<std::int16_t>(newer.probability == 0 ? 1 : 0);
  map.set(newer);
  map.restore(box);
  EXPECT_EQ(map.size(), size);
  EXPECT_EQ(map.find(newer.key)->probability, newer.probability);
  PublishedMap expected;
  fill(expected, nullptr);
  expected.set(newer);
  EXPECT_EQ(map.checksum(), expected.checksum());

  // A box that will not come back.
  const PublishedMap::Held gone = map.evict(lo, hi);
  map.forget(gone);
  EXPECT_EQ(map.size(), outside.size());
  EXPECT_EQ(map.checksum(), outside.checksum());
  EXPECT_EQ(map.held().cells, 0u);
}

}  // namespace
