// The held-out scorer and the return scorer on one straight ray through a hand-made map, every count by hand.
#include <gtest/gtest.h>

#include <map>

#include "ogf/eval/held_out.hpp"
#include "ogf/eval/return_scores.hpp"

namespace {

using ogf::CellKey;
using ogf::eval::CellEstimate;

// A ray along +x from (0.05, 0.05, 0.05) to (0.57, 0.05, 0.05) at 0.1 m crosses cells x = 0..4 and ends in
// x = 5. The map: cells 0–2 free (p 0.1), 3 unknown (0.5), 4 occupied (0.6), 5 occupied (0.9).
CellEstimate mapAt(const CellKey& k) {
  static const std::map<int, CellEstimate> cells{{0, {-1, 0.1}}, {1, {-1, 0.1}}, {2, {-1, 0.1}},
                                                  {3, {0, 0.5}},  {4, {1, 0.6}},  {5, {1, 0.9}}};
  const auto it = cells.find(k.x);
  return k.y == 0 && k.z == 0 && it != cells.end() ? it->second : CellEstimate{};
}

const Eigen::Vector3d kOrigin(0.05, 0.05, 0.05);
const Eigen::Vector3d kEnd(0.57, 0.05, 0.05);

TEST(HeldOutScorer, OneRayRanksItsEndCellAgainstTheCellsItCrossed) {
  ogf::eval::HeldOutScorer scorer(0.1, 0.0, 10.0);
  scorer.add(kOrigin, kEnd, mapAt, [](const CellKey& k) { return k.x != 3 && k.x != 5; });
  const auto s = scorer.scores();
  EXPECT_EQ(s.rays, 1);
  EXPECT_EQ(s.positives, 1);
  EXPECT_EQ(s.negatives, 5);
  EXPECT_DOUBLE_EQ(s.auc, 1.0);  // 0.9 above every crossed cell
  EXPECT_DOUBLE_EQ(s.positives_occupied, 1.0);
  EXPECT_DOUBLE_EQ(s.negatives_free, 3.0 / 5.0);
  // Unseen: end cell 5 against crossed cell 3.
  EXPECT_EQ(s.unseen.positives, 1);
  EXPECT_EQ(s.unseen.negatives, 1);
  EXPECT_DOUBLE_EQ(s.unseen.auc, 1.0);
  EXPECT_DOUBLE_EQ(s.unseen.negatives_free, 0.0);
}

TEST(HeldOutScorer, TiesCountHalfAndACutRayGivesNoPositive) {
  ogf::eval::HeldOutScorer scorer(0.1, 0.0, 0.3);  // cut at 0.3 m, in cell 3: crossed cells 0–2 only
  scorer.add(kOrigin, kEnd, mapAt, [](const CellKey&) { return true; });
  auto s = scorer.scores();
  EXPECT_EQ(s.positives, 0);
  EXPECT_EQ(s.negatives, 3);
  EXPECT_DOUBLE_EQ(s.auc, 0.5);  // nothing to rank
  ogf::eval::HeldOutScorer ties(0.1, 0.0, 10.0);
  ties.add(kOrigin, kEnd, [](const CellKey&) { return CellEstimate{0, 0.5}; }, [](const CellKey&) { return true; });
  s = ties.scores();
  EXPECT_DOUBLE_EQ(s.auc, 0.5);
  EXPECT_EQ(s.unseen.positives + s.unseen.negatives, 0);
}

TEST(HeldOutScorer, RaysShorterThanMinRangeAreIgnored) {
  ogf::eval::HeldOutScorer scorer(0.1, 1.0, 10.0);
  scorer.add(kOrigin, kEnd, mapAt, [](const CellKey&) { return true; });
  EXPECT_EQ(scorer.scores().rays, 0);
}

TEST(HeldOutSplit, HoldsOutTheRequestedShareAndDependsOnTheSeed) {
  const ogf::eval::HeldOutSplit a(0.1, 1), b(0.1, 2);
  int heldA = 0, differ = 0;
  for (std::int64_t scan = 0; scan < 10; ++scan) {
    for (std::size_t ray = 0; ray < 10000; ++ray) {
      heldA += a.heldOut(scan, ray) ? 1 : 0;
      differ += a.heldOut(scan, ray) != b.heldOut(scan, ray) ? 1 : 0;
    }
  }
  EXPECT_NEAR(heldA / 100000.0, 0.1, 0.005);
  EXPECT_GT(differ, 10000);  // two independent 10 % splits differ on ~18 % of the rays
}

TEST(ReturnScorer, ClassesTheReturnCellAndTheHalfWayPoint) {
  ogf::eval::ReturnScorer scorer(0.1, 0.1, 10.0);
  scorer.add(kOrigin, kEnd, mapAt);  // end cell 5 occupied; half-way point (0.31, ...) in cell 3: unknown
  scorer.add(kOrigin, Eigen::Vector3d(0.45, 0.05, 0.05), mapAt);  // ends in cell 4 (occupied); half-way cell 2 free
  scorer.add(kOrigin, Eigen::Vector3d(0.1, 0.05, 0.05), mapAt);   // 0.05 m: shorter than from, not counted
  const auto s = scorer.scores();
  EXPECT_EQ(s.returns, 2);
  EXPECT_DOUBLE_EQ(s.occupied, 1.0);
  EXPECT_DOUBLE_EQ(s.free, 0.0);
  EXPECT_DOUBLE_EQ(s.unknown, 0.0);
  EXPECT_DOUBLE_EQ(s.halfway_free, 0.5);
}

}  // namespace
