// SlabTable (a CellKeyTable at most 3/4 full, the slabs in its slots) against std::unordered_map: random
// look-ups, additions and erases in a small key range (so probe runs collide, wrap around the table's end
// and shift back on erase), each slab carrying a value that names it, the whole table compared every few
// steps, and the table growing past several doublings.
#include <gtest/gtest.h>

#include <random>
#include <unordered_map>

#include "ogf/delta/slab_table.hpp"

namespace ogf::delta {
namespace {

// The slab's name: the probability of its cell 0.
std::int16_t nameOf(const PublishedBlock& block) { return block.at(0).probability; }

TEST(SlabTable, AgreesWithAHashMapThroughAdditionsAndErases) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(-6, 6);
  std::uniform_int_distribution<int> action(0, 9);
  SlabTable table;
  std::unordered_map<CellKey, std::int16_t, CellKeyHash> reference;
  // Every slab the reference holds is found under its key with its name, and the table holds no other.
  const auto agree = [&](int step) {
    for (const auto& [key, name] : reference) {
      const PublishedBlock* found = table.find(key);
      ASSERT_NE(found, nullptr) << "step " << step;
      ASSERT_EQ(nameOf(*found), name) << "step " << step;
    }
    std::size_t visited = 0;
    table.forEach([&](const CellKey& key, const PublishedBlock& block) {
      ++visited;
      EXPECT_EQ(reference.at(key), nameOf(block));
    });
    ASSERT_EQ(visited, reference.size()) << "step " << step;
  };
  std::int16_t next = 0;
  std::size_t erased = 0;
  for (int step = 0; step < 20000; ++step) {
    const CellKey key{coord(rng), coord(rng), coord(rng) * 1000};
    if (action(rng) < 4) {
      const bool had = reference.erase(key) != 0;
      ASSERT_EQ(table.erase(key), had) << "step " << step;
      ASSERT_EQ(table.find(key), nullptr) << "step " << step;
      erased += static_cast<std::size_t>(had);
    } else {
      const bool had = table.find(key) != nullptr;
      PublishedBlock& block = table.obtain(key);
      const auto [it, fresh] = reference.emplace(key, next);
      ASSERT_EQ(had, !fresh) << "step " << step;
      if (fresh) {
        ASSERT_EQ(block.size(), 0u) << "a new slab is empty";
        block.put(0, {next, 1, 0.5F});
        next = static_cast<std::int16_t>((next + 1) % 10000);
      }
      ASSERT_EQ(nameOf(block), it->second) << "step " << step;
    }
    ASSERT_EQ(table.size(), reference.size());
    if (step % 97 == 0) agree(step);
  }
  agree(20000);
  EXPECT_GT(erased, 1000u);
  EXPECT_GT(table.size(), 1000u) << "the table should have grown past its first size";
  EXPECT_LE(table.size() * 4, table.capacity() * 3) << "at most 3/4 full";
  table.clear();
  EXPECT_EQ(table.size(), 0u);
  EXPECT_EQ(table.find(CellKey{0, 0, 0}), nullptr);
}

// A table moved from holds nothing (its count included) and takes new slabs like a new one.
TEST(SlabTable, MovedFromTableIsEmptyAndUsable) {
  SlabTable table;
  for (int x = 0; x < 100; ++x) table.obtain({x, 0, 0}).put(0, {static_cast<std::int16_t>(x), 0, 0.0f});
  SlabTable moved(std::move(table));
  EXPECT_EQ(moved.size(), 100u);
  EXPECT_EQ(table.size(), 0u);  // NOLINT(bugprone-use-after-move): what a moved-from table says is the point
  EXPECT_EQ(table.find({5, 0, 0}), nullptr);
  table.obtain({7, 0, 0}).put(0, {7, 0, 0.0f});
  EXPECT_EQ(table.size(), 1u);
  SlabTable assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.size(), 100u);
  EXPECT_EQ(moved.size(), 0u);  // NOLINT(bugprone-use-after-move)
  ASSERT_NE(assigned.find({42, 0, 0}), nullptr);
  EXPECT_EQ(nameOf(*assigned.find({42, 0, 0})), 42);
}

}  // namespace
}  // namespace ogf::delta
