#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "ogf/navigation/column_rule.hpp"
#include "ogf/navigation/nav_band.hpp"

namespace ogf::navigation {
namespace {

TEST(NavBand, HoldsTheLayersWhoseCentresLieInTheBandEdgesIncluded) {
  NavBand band;  // floor 0, 0.25 .. 1.5 m
  const auto l = band.layers(0.2);
  // Centres 0.1 (floor), 0.3, ..., 1.5 (on the edge, in), 1.7 (out).
  EXPECT_EQ(l.lo, 1);
  EXPECT_EQ(l.hi, 7);
  EXPECT_EQ(l.count(), 7);
  band.floor_z = -1.0;
  const auto lower = band.layers(0.2);
  EXPECT_EQ(lower.lo, -4);  // centre -0.7 = -1 + 0.3
  EXPECT_EQ(lower.hi, 2);   // centre 0.5
}

TEST(NavBand, FreeLayersNeededIsTheFractionOfTheBandRoundedUpAndAtLeastOne) {
  NavBand band;
  EXPECT_EQ(band.freeLayersNeeded(0.2), 4);  // half of 7, rounded up
  band.min_free_fraction = 0.0;
  EXPECT_EQ(band.freeLayersNeeded(0.2), 1);
  band.min_free_fraction = 1.0;
  EXPECT_EQ(band.freeLayersNeeded(0.2), 7);
}

TEST(NavBand, ValidateNamesTheFieldThatIsWrong) {
  NavBand band;
  EXPECT_TRUE(band.validate(0.2).ok());
  band.max_height = 0.1;
  ASSERT_FALSE(band.validate(0.2).ok());
  EXPECT_NE(band.validate(0.2).error().message.find("nav.max_height"), std::string::npos);
  band = {};
  band.min_free_fraction = 1.5;
  EXPECT_NE(band.validate(0.2).error().message.find("nav.min_free_fraction"), std::string::npos);
  band = {};
  band.min_height = 0.31;
  band.max_height = 0.32;  // no centre of a 0.2 m layer in between
  ASSERT_FALSE(band.validate(0.2).ok());
  EXPECT_NE(band.validate(0.2).error().message.find("holds no cell"), std::string::npos);
  band = {};
  band.floor_z = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(band.validate(0.2).error().message.find("nav.floor_z"), std::string::npos);
}

TEST(CellCost, IsTheProbabilityWithoutVarianceAndRisesWithVariance) {
  EXPECT_EQ(cellCost(0.2, 0.0), 20);
  EXPECT_EQ(cellCost(0.9, 0.0), 90);
  EXPECT_EQ(cellCost(0.5, 0.0), 50);
  // Same predictive probability, less certainty: a higher cost.
  EXPECT_GT(cellCost(0.2, 1.0), cellCost(0.2, 0.1));
  EXPECT_GT(cellCost(0.2, 0.1), cellCost(0.2, 0.0));
  // Monotonic in the probability.
  for (int i = 1; i < 100; ++i) EXPECT_LE(cellCost((i - 1) / 100.0, 0.3), cellCost(i / 100.0, 0.3)) << i;
  // Bounds and junk.
  EXPECT_EQ(cellCost(0.0, 0.0), 0);
  EXPECT_EQ(cellCost(1.0, 0.0), 100);
  EXPECT_EQ(cellCost(0.2, -1.0), 20);
  EXPECT_EQ(cellCost(std::numeric_limits<double>::quiet_NaN(), 0.0), 50);
}

// 100 · Φ(x) rounded, computed here from erfc as the cost's definition says.
std::int8_t roundedPercentOfPhi(double x) {
  return static_cast<std::int8_t>(std::lround(std::clamp(0.5 * std::erfc(-x / std::sqrt(2.0)), 0.0, 1.0) * 100));
}

TEST(CellCost, AtEveryProbitItIsOneHundredPhiRounded) {
  // Where the rounded value steps (Φ(x) = (k + 0.5) / 100), every double within 2000 of the step either side.
  int steps_checked = 0;
  for (int k = 0; k < 100; ++k) {
    double x = 0;
    for (double lo = -10, hi = 10, i = 0; i < 200; ++i) {  // Φ(x) ≈ (k + 0.5) / 100
      x = (lo + hi) / 2;
      (0.5 * std::erfc(-x / std::sqrt(2.0)) < (k + 0.5) / 100 ? lo : hi) = x;
    }
    double below = x, above = x;
    for (int i = 0; i < 2000; ++i) {
      below = std::nextafter(below, -1e9);
      above = std::nextafter(above, 1e9);
      ASSERT_EQ(costAtProbit(below), roundedPercentOfPhi(below)) << "k " << k << " x " << below;
      ASSERT_EQ(costAtProbit(above), roundedPercentOfPhi(above)) << "k " << k << " x " << above;
    }
    EXPECT_EQ(roundedPercentOfPhi(below), k);
    EXPECT_EQ(roundedPercentOfPhi(above), k + 1);
    ++steps_checked;
  }
  EXPECT_EQ(steps_checked, 100);
  // And a dense sweep, the tails and the infinities.
  for (double x = -12; x <= 12; x += 1e-4) ASSERT_EQ(costAtProbit(x), roundedPercentOfPhi(x)) << x;
  EXPECT_EQ(costAtProbit(-std::numeric_limits<double>::infinity()), 0);
  EXPECT_EQ(costAtProbit(std::numeric_limits<double>::infinity()), 100);
}

TEST(ClassifyColumn, OccupiedWhenAnyCellIsFreeWhenEnoughLayersAreElseUnknown) {
  const BandCell unseen{};
  const BandCell free{10, kClassFree};
  const BandCell wall{95, kClassOccupied};
  const BandCell unsure{50, kClassUnknown};
  const BandCell column_wall[] = {free, free, wall, unseen};
  EXPECT_EQ(classifyColumn(column_wall, 2), (NavColumn{95, kClassOccupied}));
  const BandCell column_free[] = {free, {30, kClassFree}, unsure, unseen};
  EXPECT_EQ(classifyColumn(column_free, 2), (NavColumn{50, kClassFree}));  // cost: the worst known cell
  EXPECT_EQ(classifyColumn(column_free, 3), NavColumn{});                 // too few free layers
  const BandCell column_unseen[] = {unseen, unseen};
  EXPECT_EQ(classifyColumn(column_unseen, 0), NavColumn{});  // at least one free layer, even when 0 asked
  EXPECT_EQ(NavColumn{}.cost, kUnknownCost);
}

}  // namespace
}  // namespace ogf::navigation
