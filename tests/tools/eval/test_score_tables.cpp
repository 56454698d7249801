// ogf-eval's pieces that turn a run into its table: the cells rays ended in land on the truth grid by the
// file's x-fastest order and only occupied measurements inside the grid count; a map's column counts its
// occupied and free estimates; the table prints one fixed-width column per map, with the gap rows only
// when gaps were scored.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ogf/eval/ray_ends.hpp"
#include "ogf/eval/score_tables.hpp"

namespace {

namespace ev = ogf::eval;

// A 3x2x2 grid starting at key (10, 20, 30): every cell free except the occupied one at index 7.
ogf::sim::GroundTruth smallTruth() {
  ogf::sim::GroundTruth t;
  t.min_key = ogf::CellKey{10, 20, 30};
  t.size = {3, 2, 2};
  t.cells.assign(12, static_cast<std::uint8_t>(ogf::sim::CellClass::Free));
  t.cells[7] = static_cast<std::uint8_t>(ogf::sim::CellClass::Occupied);
  return t;
}

TEST(ScoreTables, RayEndsMarkOccupiedMeasurementsInsideTheGridByXFastestIndex) {
  const auto truth = smallTruth();
  std::vector<std::uint8_t> ray_end(truth.cells.size(), 0);
  const std::vector<ogf::Measurement> ms{
      {ogf::CellKey{11, 20, 31}, ogf::Measurement::kOccupied},  // 1 + 3 * (0 + 2 * 1) = 7
      {ogf::CellKey{12, 21, 30}, ogf::Measurement::kFree},      // free: no ray ended there
      {ogf::CellKey{13, 20, 30}, ogf::Measurement::kOccupied},  // x beyond the grid
      {ogf::CellKey{10, 19, 30}, ogf::Measurement::kOccupied},  // y before the grid
  };
  ev::markRayEnds(truth, ms, ray_end);
  std::vector<std::uint8_t> expected(truth.cells.size(), 0);
  expected[7] = 1;
  EXPECT_EQ(ray_end, expected);
}

TEST(ScoreTables, ColumnCountsOccupiedAndFreeEstimates) {
  const auto truth = smallTruth();
  std::vector<ev::CellEstimate> est(truth.cells.size(), ev::CellEstimate{-1, 0.1});
  est[7] = ev::CellEstimate{1, 0.9};
  est[0] = ev::CellEstimate{0, 0.5};
  const auto col = ev::makeColumn("OGF", truth, est, {}, "12");
  EXPECT_EQ(col.occupied_cells, 1);
  EXPECT_EQ(col.free_cells, 10);
  EXPECT_EQ(col.scores.correct, 11);
  EXPECT_EQ(col.map_cells, "12");
}

TEST(ScoreTables, TableHasOneFixedWidthColumnPerMapAndGapRowsOnlyWhenScored) {
  const auto truth = smallTruth();
  const std::vector<ev::CellEstimate> est(truth.cells.size(), ev::CellEstimate{-1, 0.1});
  const std::vector<ev::MapColumn> cols{ev::makeColumn("OGF", truth, est, {}, "12"),
                                        ev::makeColumn("OctoMap", truth, est, {}, "3 leaves")};
  const std::string without = ev::scoreTable(cols, false);
  EXPECT_EQ(without.substr(0, without.find('\n') + 1),
            "metric                                      OGF      OctoMap\n");
  EXPECT_NE(without.find("cells held by the map                        12     3 leaves\n"), std::string::npos);
  EXPECT_EQ(without.find("gap filling"), std::string::npos);
  EXPECT_NE(ev::scoreTable(cols, true).find("gap filling (share)"), std::string::npos);
}

}  // namespace
