#include <gtest/gtest.h>

#include "ogf/eval/nav_scores.hpp"

namespace ogf::eval {
namespace {

namespace nav = navigation;

// A 3 x 1 x 8 truth at 0.2 m: column 0 free air, column 1 a wall in the band, column 2 inside a solid.
sim::GroundTruth truth() {
  sim::GroundTruth t;
  t.resolution = 0.2;
  t.min_key = {0, 0, 0};
  t.size = {3, 1, 8};
  t.cells.assign(24, static_cast<std::uint8_t>(sim::CellClass::Free));
  t.cells[1 + 3 * 4] = static_cast<std::uint8_t>(sim::CellClass::Occupied);  // column 1, layer 4
  for (std::size_t z = 0; z < 8; ++z) t.cells[2 + 3 * z] = static_cast<std::uint8_t>(sim::CellClass::Unobservable);
  return t;
}

nav::NavGrid grid(std::int8_t c0, std::int8_t c1, std::int8_t c2) {
  nav::NavGrid g;
  g.resolution = 0.2;
  g.origin = {0, 0};
  g.width = 3;
  g.height = 1;
  g.column_class = {c0, c1, c2};
  g.cost = {0, 0, 0};
  return g;
}

TEST(NavScores, ScoresTheTruthsFreeAndOccupiedColumnsAndLeavesTheOthersOut) {
  const auto t = truth();
  const auto right = scoreNavGrid(t, grid(nav::kClassFree, nav::kClassOccupied, nav::kClassOccupied));
  EXPECT_EQ(right.truth_free, 1u);
  EXPECT_EQ(right.truth_occupied, 1u);
  EXPECT_DOUBLE_EQ(right.accuracy(), 1.0);
  EXPECT_DOUBLE_EQ(right.coverage(), 1.0);
  const auto wrong = scoreNavGrid(t, grid(nav::kClassOccupied, nav::kClassFree, nav::kClassFree));
  EXPECT_DOUBLE_EQ(wrong.freeAsOccupied(), 1.0);
  EXPECT_DOUBLE_EQ(wrong.occupiedAsFree(), 1.0);
  EXPECT_DOUBLE_EQ(wrong.accuracy(), 0.0);
  const auto unknown = scoreNavGrid(t, grid(nav::kClassUnknown, nav::kClassOccupied, nav::kClassUnknown));
  EXPECT_DOUBLE_EQ(unknown.accuracy(), 0.5);
  EXPECT_DOUBLE_EQ(unknown.coverage(), 0.5);
  EXPECT_NE(navScoreTable(unknown, grid(0, 0, 0)).find("nav accuracy                0.5000"), std::string::npos);
}

TEST(NavScores, AWallAboveTheBandLeavesTheColumnFree) {
  auto t = truth();
  auto g = grid(nav::kClassFree, nav::kClassFree, nav::kClassUnknown);
  g.band.max_height = 0.8;  // layers 1..3 at 0.2 m: the wall at layer 4 is above
  const auto s = scoreNavGrid(t, g);
  EXPECT_EQ(s.truth_free, 2u);
  EXPECT_EQ(s.truth_occupied, 0u);
  EXPECT_DOUBLE_EQ(s.accuracy(), 1.0);
}

}  // namespace
}  // namespace ogf::eval
