// The slots the page's boxes live in: occupied cells hold one each, a cell that stops being occupied frees
// its slot for the next, every change is reported once, and a reset renumbers without holes.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "ogf/view/occupied_slots.hpp"

namespace {

using ogf::delta::PublishedCell;
using ogf::view::kEmptySlot;
using ogf::view::OccupiedSlots;

constexpr std::int8_t kOcc = ogf::map_delta_t::CLASS_OCCUPIED;
constexpr std::int8_t kFree = ogf::map_delta_t::CLASS_FREE;
constexpr std::int8_t kUnknown = ogf::map_delta_t::CLASS_UNKNOWN;

PublishedCell cell(int x, int y, int z, std::int8_t cls, std::int16_t p = 9000, float var = 0.25f) {
  return {{x, y, z}, p, cls, var};
}

TEST(OccupiedSlots, OnlyOccupiedCellsTakeSlots) {
  OccupiedSlots s;
  s.set(cell(0, 0, 0, kOcc));
  s.set(cell(1, 0, 0, kFree, 1000));
  s.set(cell(2, 0, 0, kUnknown, 5000));
  EXPECT_EQ(s.occupied(), 1u);
  EXPECT_EQ(s.slotCount(), 1u);
  EXPECT_EQ(s.slot(0).key, (ogf::CellKey{0, 0, 0}));
  EXPECT_EQ(s.slot(0).probability, 9000);
  EXPECT_FLOAT_EQ(s.slot(0).variance, 0.25f);
}

TEST(OccupiedSlots, ACellKeepsItsSlotAndAFreedSlotIsReused) {
  OccupiedSlots s;
  s.set(cell(0, 0, 0, kOcc));
  s.set(cell(1, 0, 0, kOcc));
  s.set(cell(2, 0, 0, kOcc));
  s.takeChanged();
  s.set(cell(1, 0, 0, kOcc, 9500));  // same cell, new probability: same slot
  EXPECT_EQ(s.takeChanged(), std::vector<std::uint32_t>{1});
  EXPECT_EQ(s.slot(1).probability, 9500);
  s.set(cell(1, 0, 0, kFree, 2000));  // no longer occupied: slot 1 is emptied
  EXPECT_EQ(s.slot(1).probability, kEmptySlot);
  EXPECT_EQ(s.occupied(), 2u);
  s.set(cell(7, 7, 7, kOcc));  // takes the freed slot, the page needs no more boxes
  EXPECT_EQ(s.slotCount(), 3u);
  EXPECT_EQ(s.slot(1).key, (ogf::CellKey{7, 7, 7}));
  EXPECT_EQ(s.takeChanged(), std::vector<std::uint32_t>{1});  // once, though changed twice
  EXPECT_TRUE(s.takeChanged().empty());
}

TEST(OccupiedSlots, FollowsAnyStreamOfChangesExactly) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> coord(0, 15), cls(-1, 1);
  OccupiedSlots s;
  std::map<ogf::CellKey, bool> truth;
  std::vector<ogf::view::SlotCell> mirror;  // what a page holds after applying every change
  for (int round = 0; round < 50; ++round) {
    for (int i = 0; i < 200; ++i) {
      const auto c = cell(coord(rng), coord(rng), coord(rng) / 4, static_cast<std::int8_t>(cls(rng)));
      s.set(c);
      truth[c.key] = c.cell_class == kOcc;
    }
    mirror.resize(s.slotCount(), {{}, kEmptySlot, 0.0f});
    for (const auto i : s.takeChanged()) mirror[i] = s.slot(i);
  }
  std::set<ogf::CellKey> drawn;
  for (const auto& m : mirror) {
    if (m.probability != kEmptySlot) {
      EXPECT_TRUE(drawn.insert(m.key).second) << "a cell in two slots";
    }
  }
  std::set<ogf::CellKey> occupied;
  for (const auto& [k, occ] : truth)
    if (occ) occupied.insert(k);
  EXPECT_EQ(drawn, occupied);
  EXPECT_EQ(s.occupied(), occupied.size());
}

TEST(OccupiedSlots, ResetNumbersFromZeroAndAsksForAFullFrame) {
  OccupiedSlots s;
  for (int i = 0; i < 10; ++i) s.set(cell(i, 0, 0, kOcc));
  for (int i = 0; i < 10; i += 2) s.set(cell(i, 0, 0, kFree));
  EXPECT_FALSE(s.takeFullPending());
  const std::vector<PublishedCell> keyframe{cell(5, 5, 5, kOcc), cell(6, 5, 5, kFree), cell(7, 5, 5, kOcc)};
  s.reset(keyframe);
  EXPECT_TRUE(s.takeFullPending());
  EXPECT_FALSE(s.takeFullPending());
  EXPECT_EQ(s.slotCount(), 2u);
  EXPECT_EQ(s.filledSlots(), (std::vector<std::uint32_t>{0, 1}));
  EXPECT_TRUE(s.takeChanged().empty());  // the full frame carries them
}

TEST(OccupiedSlots, AtACoarserLevelABoxStaysWhileAnyOfItsCellsIsOccupied) {
  OccupiedSlots s;
  s.reset({}, 2);
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) s.set(cell(x, y, z, kOcc));
  s.set(cell(-1, 0, 0, kOcc));  // the box below 0 is another box: -1 / 2 rounds down to -1
  EXPECT_EQ(s.occupiedCells(), 9u);
  EXPECT_EQ(s.occupied(), 2u);
  EXPECT_EQ(s.slot(0).key, (ogf::CellKey{0, 0, 0}));
  EXPECT_EQ(s.slot(1).key, (ogf::CellKey{-1, 0, 0}));
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y) s.set(cell(x, y, 0, kFree));
  s.set(cell(1, 1, 1, kUnknown));
  EXPECT_EQ(s.slot(0).probability, 9000);  // three cells still hold the box
  s.set(cell(0, 0, 1, kFree));
  s.set(cell(0, 1, 1, kFree));
  EXPECT_EQ(s.slot(0).probability, 9000);
  s.set(cell(1, 0, 1, kFree));  // the last one
  EXPECT_EQ(s.slot(0).probability, kEmptySlot);
  EXPECT_EQ(s.occupied(), 1u);
  EXPECT_EQ(s.occupiedCells(), 1u);
}

TEST(OccupiedSlots, LevelOfDetailIsTheFinestWithinTheBudget) {
  std::vector<PublishedCell> cells;
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 40; ++y) cells.push_back(cell(x, y, 0, kOcc));  // 1600 cells in one layer
  cells.push_back(cell(100, 100, 0, kFree));                           // free cells take no box
  EXPECT_EQ(ogf::view::chooseLod(cells, 1600), 1);
  EXPECT_EQ(ogf::view::chooseLod(cells, 1599), 2);  // 20 x 20 boxes
  EXPECT_EQ(ogf::view::chooseLod(cells, 400), 2);
  EXPECT_EQ(ogf::view::chooseLod(cells, 399), 4);
  OccupiedSlots s;
  s.reset(cells, ogf::view::chooseLod(cells, 400));
  EXPECT_EQ(s.lod(), 2);
  EXPECT_EQ(s.occupied(), 400u);
  EXPECT_EQ(s.occupiedCells(), 1600u);
}

}  // namespace
