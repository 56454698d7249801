// BlockTable against std::unordered_map: random inserts, look-ups and erases in a small key range (so
// probe runs collide, wrap around the table's end and shift back on erase), every key checked after every
// step, and the table growing past several doublings.
#include "ogf/filter/block_table.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <unordered_map>

namespace ogf::filter {
namespace {

TEST(BlockTable, AgreesWithAHashMapThroughInsertsAndErases) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(-6, 6);
  std::uniform_int_distribution<int> action(0, 9);
  BlockTable<int> table;
  std::unordered_map<CellKey, int, CellKeyHash> reference;
  int next = 0;
  std::size_t erased = 0;
  for (int step = 0; step < 20000; ++step) {
    const CellKey key{coord(rng), coord(rng), coord(rng) * 1000};
    if (action(rng) < 4) {
      const bool had = reference.erase(key) != 0;
      ASSERT_EQ(table.erase(key), had) << "step " << step;
      erased += static_cast<std::size_t>(had);
    } else {
      bool inserted = false;
      int& value = table.findOrInsert(
          key, [&] { return std::make_unique<int>(next); }, inserted);
      const auto [it, fresh] = reference.emplace(key, next);
      ASSERT_EQ(inserted, fresh) << "step " << step;
      ASSERT_EQ(value, it->second);
      ++next;
    }
    ASSERT_EQ(table.size(), reference.size());
    if (step % 97 == 0) {
      for (int x = -6; x <= 6; ++x) {
        for (int y = -6; y <= 6; ++y) {
          for (int z = -6; z <= 6; ++z) {
            const CellKey k{x, y, z * 1000};
            const auto it = reference.find(k);
            const int* found = table.find(k);
            ASSERT_EQ(found != nullptr, it != reference.end()) << "step " << step;
            if (found != nullptr) {
              ASSERT_EQ(*found, it->second);
            }
          }
        }
      }
    }
  }
  EXPECT_GT(erased, 1000u);
  EXPECT_GT(table.size(), 1000u) << "the table should have grown past its first size";
  std::size_t visited = 0;
  table.forEach([&](const CellKey& k, const int& v) {
    ++visited;
    EXPECT_EQ(reference.at(k), v);
  });
  EXPECT_EQ(visited, reference.size());
}

TEST(BlockTable, ValuesKeepTheirAddressWhenTheTableGrows) {
  BlockTable<int> table;
  bool inserted = false;
  int* first = &table.findOrInsert(
      {1, 2, 3}, [] { return std::make_unique<int>(7); }, inserted);
  for (int i = 0; i < 5000; ++i)
    table.findOrInsert(
        {i, -i, i}, [&] { return std::make_unique<int>(i); }, inserted);
  EXPECT_EQ(table.find({1, 2, 3}), first);
  EXPECT_EQ(*first, 7);
  EXPECT_FALSE(table.erase({100000, 0, 0}));
  EXPECT_EQ(table.find({100000, 0, 0}), nullptr);
}

}  // namespace
}  // namespace ogf::filter
