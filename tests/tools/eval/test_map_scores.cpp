// ogf-eval's scores on a hand-made truth and map, every answer computed by hand in the comments.
#include <gtest/gtest.h>

#include <vector>

#include "ogf/eval/map_scores.hpp"

namespace {

using ogf::eval::CellEstimate;
using ogf::eval::rocAuc;
using ogf::eval::scoreMap;

constexpr std::uint8_t F = 0, O = 1, U = 2;  // truth classes: free, occupied, unobservable

// Eight truth cells: 3 occupied, 4 free, 1 unobservable.
//   i  truth  class  p     ray end
//   0  O      +1     0.9   1        true occupied
//   1  O      +1     0.7   0        true occupied, a gap filled
//   2  O       0     0.5   0        unknown: wrong; a gap not filled
//   3  F      -1     0.1   -        true free
//   4  F      -1     0.2   -        true free
//   5  F      +1     0.8   -        false occupied
//   6  F       0     0.5   -        unknown: wrong
//   7  U      +1     0.99  -        left out
const std::vector<std::uint8_t> kTruth{O, O, O, F, F, F, F, U};
const std::vector<CellEstimate> kMap{{1, 0.9}, {1, 0.7}, {0, 0.5}, {-1, 0.1}, {-1, 0.2}, {1, 0.8}, {0, 0.5}, {1, 0.99}};
const std::vector<std::uint8_t> kRayEnd{1, 0, 0, 0, 0, 0, 0, 1};

TEST(MapScores, HandComputedCountsOnAnEightCellWorld) {
  const auto s = scoreMap(kTruth, kMap, kRayEnd);
  EXPECT_EQ(s.known, 7);
  EXPECT_EQ(s.truth_occupied, 3);
  EXPECT_EQ(s.truth_free, 4);
  EXPECT_EQ(s.true_occupied, 2);
  EXPECT_EQ(s.false_occupied, 1);
  EXPECT_EQ(s.true_free, 2);
  EXPECT_EQ(s.false_free, 0);
  EXPECT_EQ(s.classified, 5);
  EXPECT_EQ(s.correct, 4);
  EXPECT_EQ(s.gap_cells, 2);
  EXPECT_EQ(s.gap_filled, 1);
  EXPECT_EQ(s.false_filled, 1);  // cell 5: truly free, no ray ended there, classed occupied
}

TEST(MapScores, AccuracyCountsUnknownAsWrongAndLeavesUnobservableOut) {
  const auto s = scoreMap(kTruth, kMap, kRayEnd);
  EXPECT_DOUBLE_EQ(s.accuracy, 4.0 / 7.0);   // eq. (13): cells 0, 1, 3, 4 right of 7 known
  EXPECT_DOUBLE_EQ(s.precision, 2.0 / 3.0);  // classified occupied: 0, 1 (right), 5 (wrong)
  EXPECT_DOUBLE_EQ(s.recall, 2.0 / 3.0);     // truth occupied: 0, 1 found, 2 missed
  EXPECT_DOUBLE_EQ(s.coverage, 5.0 / 7.0);   // classified: all but 2 and 6
  EXPECT_DOUBLE_EQ(s.gap_fill, 0.5);
}

TEST(MapScores, AucOfTheEightCellWorldByPairs) {
  // Positives {0.9, 0.7, 0.5} against negatives {0.1, 0.2, 0.8, 0.5}: 12 pairs.
  // 0.9 beats all 4; 0.7 beats 0.1, 0.2, 0.5 (3); 0.5 beats 0.1, 0.2 and ties 0.5 (2.5). (4 + 3 + 2.5) / 12.
  const auto s = scoreMap(kTruth, kMap, kRayEnd);
  EXPECT_DOUBLE_EQ(s.auc, 9.5 / 12.0);
}

TEST(MapScores, WithoutRayEndsNoGapIsScored) {
  const auto s = scoreMap(kTruth, kMap, {});
  EXPECT_EQ(s.gap_cells, 0);
  EXPECT_EQ(s.gap_filled, 0);
  EXPECT_DOUBLE_EQ(s.accuracy, 4.0 / 7.0);
}

TEST(MapScores, AnEmptyMapIsUnknownEverywhereSoAccuracyAndCoverageAreZero) {
  const std::vector<CellEstimate> empty(kTruth.size());
  const auto s = scoreMap(kTruth, empty, kRayEnd);
  EXPECT_EQ(s.accuracy, 0.0);
  EXPECT_EQ(s.coverage, 0.0);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_DOUBLE_EQ(s.auc, 0.5);  // every probability the prior: all pairs tie
}

TEST(MapScores, SweptCellsLeftOccupiedAreCountedAmongTheTrulyFreeOnly) {
  // Cells 1 (occupied: a solid now stands there), 4 (free, classed free) and 5 (free, classed occupied)
  // were swept by a moving solid.
  const std::vector<std::uint8_t> swept{0, 1, 0, 0, 1, 1, 0, 0};
  const auto s = ogf::eval::scoreSwept(kTruth, swept, kMap);
  EXPECT_EQ(s.cells, 2);
  EXPECT_EQ(s.left_occupied, 1);
}

TEST(RocAuc, PerfectSeparationIsOneAndReversedIsZero) {
  EXPECT_DOUBLE_EQ(rocAuc(std::vector<double>{0.8, 0.9}, std::vector<double>{0.1, 0.2, 0.3}), 1.0);
  EXPECT_DOUBLE_EQ(rocAuc(std::vector<double>{0.1}, std::vector<double>{0.8, 0.9}), 0.0);
}

TEST(RocAuc, EqualsTheShareOfPositiveNegativePairsOrderedRightWithTiesHalf) {
  const std::vector<double> pos{0.3, 0.6, 0.6, 0.9, 0.2};
  const std::vector<double> neg{0.1, 0.6, 0.4, 0.3};
  double pairs = 0;
  for (double p : pos)
    for (double n : neg) pairs += p > n ? 1.0 : (p == n ? 0.5 : 0.0);
  EXPECT_DOUBLE_EQ(rocAuc(pos, neg), pairs / static_cast<double>(pos.size() * neg.size()));
}

TEST(RocAuc, AnEmptyClassGivesOneHalf) {
  EXPECT_DOUBLE_EQ(rocAuc(std::vector<double>{}, std::vector<double>{0.2}), 0.5);
}

}  // namespace

namespace {

// Two maps of four known cells and one unobservable: each alone classifies two, together three, of which
// they contradict each other on one.
TEST(UnionCoverage, CountsAKnownCellOnceWhenAnyMapClassifiesItAndApartWhereMapsContradict) {
  using ogf::eval::CellEstimate;
  const std::vector<std::uint8_t> truth = {0, 1, 0, 1, 2};
  const std::vector<CellEstimate> a = {{-1, 0.1}, {1, 0.9}, {0, 0.5}, {0, 0.5}, {1, 0.9}};
  const std::vector<CellEstimate> b = {{-1, 0.1}, {-1, 0.2}, {0, 0.5}, {1, 0.8}, {1, 0.9}};
  EXPECT_DOUBLE_EQ(ogf::eval::unionCoverage(truth, {a}).any, 0.5);
  EXPECT_DOUBLE_EQ(ogf::eval::unionCoverage(truth, {a}).consistent, 0.5);
  const auto both = ogf::eval::unionCoverage(truth, {a, b});
  EXPECT_DOUBLE_EQ(both.any, 0.75) << "the unobservable cell never counts";
  EXPECT_DOUBLE_EQ(both.consistent, 0.5) << "cell 1 is occupied in a, free in b";
  EXPECT_DOUBLE_EQ(ogf::eval::unionCoverage(truth, {}).any, 0.0);
}

}  // namespace
