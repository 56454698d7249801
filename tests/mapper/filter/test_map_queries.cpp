// Queries answer Φ(m), predictive probability, class, variance and entropy consistently, unallocated cells
// answer with the prior, and iteration and memory accounting cover every allocated cell.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/inverse_mills.hpp"
#include "ogf/filter/map_queries.hpp"
#include "ogf/filter/occupancy.hpp"

namespace ogf::filter {
namespace {

BandedOgf wallMap() {
  FilterConfig config;
  auto map = BandedOgf::create(config);
  std::vector<Measurement> batch;
  for (int x = 0; x < 10; ++x) {
    for (int y = 0; y < 10; ++y) {
      batch.push_back({{x, y, 0}, static_cast<std::int8_t>(x == 5 ? 1 : -1)});
    }
  }
  for (int k = 0; k < 5; ++k) {
    map->update(batch);
  }
  return std::move(map).value();
}

TEST(MapQueries, OccupiedFreeAndUnknownCellsAreClassifiedByEquationThree) {
  const BandedOgf map = wallMap();
  const CellQuery wall = queryCell(map, {5, 5, 0});
  const CellQuery open = queryCell(map, {2, 5, 0});
  const CellQuery far = queryCell(map, {500, 500, 500});
  EXPECT_EQ(wall.occupancyClass, 1);
  EXPECT_GT(wall.occupancyProbability, 0.65);
  EXPECT_EQ(open.occupancyClass, -1);
  EXPECT_LT(open.occupancyProbability, 0.35);
  EXPECT_EQ(far.occupancyClass, 0);
  EXPECT_FALSE(far.allocated);
  EXPECT_DOUBLE_EQ(far.variance, map.prior().variance());
  EXPECT_DOUBLE_EQ(far.entropyBits, 1.0);
  // Measured cells are more certain than the prior.
  EXPECT_LT(wall.variance, far.variance);
  EXPECT_LT(wall.entropyBits, 1.0);
  EXPECT_NEAR(wall.predictiveProbability, normalCdf(wall.mean / std::sqrt(1.0 + wall.variance)), 1e-15);
}

TEST(MapQueries, BoxSummaryCountsEveryCellOnce) {
  const BandedOgf map = wallMap();
  const auto box = summariseBox(map, {0, 0, 0}, {9, 9, 0});
  ASSERT_TRUE(box.ok());
  EXPECT_EQ(box->cells, 100U);
  EXPECT_EQ(box->occupied + box->free + box->unknown, 100U);
  EXPECT_EQ(box->occupied, 10U);
  EXPECT_EQ(box->free, 90U);
  EXPECT_EQ(box->allocated, 100U);
  EXPECT_FALSE(summariseBox(map, {1, 0, 0}, {0, 0, 0}).ok());
  EXPECT_FALSE(summariseBox(map, {0, 0, 0}, {1000, 1000, 1000}, 1000).ok());
}

TEST(MapQueries, IterationVisitsEveryAllocatedCellOnceInKeyOrderPerBlock) {
  const BandedOgf map = wallMap();
  std::size_t visited = 0;
  CellKey previous{};
  bool first = true;
  bool ordered = true;
  map.forEachCell([&](const CellKey& k, float m, float s) {
    ++visited;
    if (!first && blockKeyOf(k) == blockKeyOf(previous) && !(previous < k)) {
      ordered = false;
    }
    EXPECT_EQ(static_cast<double>(m), map.estimate(k).mean);
    EXPECT_EQ(static_cast<double>(s), map.estimate(k).variance);
    previous = k;
    first = false;
  });
  EXPECT_EQ(visited, map.allocatedCells());
  EXPECT_TRUE(ordered);
}

TEST(MapQueries, MemoryPerAllocatedCellIsWithinSixtyFourBytesAtTheDefaultStencil) {
  const BandedOgf map = wallMap();
  ASSERT_GT(map.allocatedCells(), 0U);
  const double perCell = static_cast<double>(map.memoryBytes()) / static_cast<double>(map.allocatedCells());
  EXPECT_LE(perCell, 64.0);
  EXPECT_GE(perCell, 4.0 * 14.0);  // mean, variance and 12 forward covariances as floats
}

}  // namespace
}  // namespace ogf::filter
