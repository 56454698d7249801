// CellMarks keeps a scan's marks either in hashed bricks (rays traversed one at a time) or, where the CPU
// has AVX-512, in a dense box (rays queued and traversed eight at a time): both must give the same
// measurements, ties and negative cells included, and a box over budget must fall back to the hashed way.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <ogf/fusion/cell_marks.hpp>
#include <ogf/fusion/ray_caster.hpp>
#include <random>
#include <vector>

#include "ray_reference.hpp"

namespace ogf::fusion {
namespace {

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d end;
};

// Rays between points of a quarter-cell grid (exact edge and corner crossings) on both sides of zero, of
// lengths from zero to tens of cells, plus some cells marked on their own.
struct Scan {
  std::vector<Ray> rays;
  std::vector<CellKey> free_cells;
  std::vector<CellKey> occupied_cells;
};

Scan gridScan(std::uint64_t seed, int rays, int reach_quarters, double resolution) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> quarter(-reach_quarters, reach_quarters);
  std::uniform_int_distribution<int> cell(-reach_quarters / 4, reach_quarters / 4);
  const auto point = [&]() -> Eigen::Vector3d {
    const double x = quarter(rng);
    const double y = quarter(rng);
    const double z = quarter(rng);
    return Eigen::Vector3d(x, y, z) * (resolution / 4.0);
  };
  Scan scan;
  for (int i = 0; i < rays; ++i) {
    Ray r{point(), point()};
    if (i % 5 == 1) r.end.z() = r.origin.z();  // in a plane of cell faces or inside one layer
    if (i % 11 == 3) r.end = r.origin;         // no cells
    scan.rays.push_back(r);
  }
  for (int i = 0; i < rays / 10; ++i) {
    for (auto* cells : {&scan.free_cells, &scan.occupied_cells}) {
      const std::int32_t x = cell(rng);
      const std::int32_t y = cell(rng);
      const std::int32_t z = cell(rng);
      cells->push_back({x, y, z});
    }
  }
  return scan;
}

std::vector<Measurement> marked(CellMarks& marks, const Scan& scan, double resolution) {
  marks.clear();
  for (const Ray& r : scan.rays) marks.markFree(RayCaster(r.origin, r.end, resolution));
  for (const CellKey& k : scan.free_cells) marks.markFree(k);
  for (const CellKey& k : scan.occupied_cells) marks.markOccupied(k);
  MeasurementBuffer out;
  marks.appendSorted(out);
  return {out.begin(), out.end()};
}

// What the marks must be: every cell of each ray by the brute-force traversal, free, then the single cells,
// occupied winning.
std::vector<Measurement> expected(const Scan& scan, double resolution) {
  std::map<CellKey, std::int8_t, BrickOrder> want;
  for (const Ray& r : scan.rays) {
    for (const CellKey& k : test::referenceRayCells(r.origin, r.end, resolution))
      want.emplace(k, Measurement::kFree);
  }
  for (const CellKey& k : scan.free_cells) want.emplace(k, Measurement::kFree);
  for (const CellKey& k : scan.occupied_cells) want[k] = Measurement::kOccupied;
  std::vector<Measurement> out;
  for (const auto& [k, y] : want) out.push_back({k, y});
  return out;
}

TEST(CellMarks, HashedMarksMatchTheBruteForceCells) {
  CellMarks hashed(false);
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const Scan scan = gridScan(seed, 301, 120, 0.25);
    ASSERT_EQ(marked(hashed, scan, 0.25), expected(scan, 0.25)) << "seed " << seed;
    EXPECT_FALSE(hashed.lastScanBoxed());
  }
}

TEST(CellMarks, BoxedMarksMatchTheBruteForceCellsTiesIncluded) {
  if (!CellMarks::boxAvailable())
    GTEST_SKIP() << "this CPU has no AVX-512: CellMarks always keeps hashed bricks here";
  CellMarks boxed;
  int rays_with_ties = 0;
  // Ray counts that fill the eight lanes unevenly, lengths from 0 to about 60 cells.
  for (const int rays : {1, 7, 8, 9, 301, 2000}) {
    const Scan scan = gridScan(static_cast<std::uint64_t>(rays), rays, 120, 0.25);
    for (const Ray& r : scan.rays) {
      const auto cells = static_cast<std::int64_t>(test::referenceRayCells(r.origin, r.end, 0.25).size());
      if (cells < RayCaster(r.origin, r.end, 0.25).maxCells()) ++rays_with_ties;
    }
    ASSERT_EQ(marked(boxed, scan, 0.25), expected(scan, 0.25)) << rays << " rays";
    EXPECT_TRUE(boxed.lastScanBoxed());
  }
  EXPECT_GT(rays_with_ties, 100) << "the grid should produce many edge and corner ties";
}

TEST(CellMarks, BoxedAndHashedAgreeOnAMovingLidarsRays) {
  if (!CellMarks::boxAvailable())
    GTEST_SKIP() << "this CPU has no AVX-512: CellMarks always keeps hashed bricks here";
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Scan scan;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d origin(-13.1 + 0.002 * i, 7.05 - 0.001 * i, -0.7);
    // A VLP-16's field of view: all around, ±15° in elevation.
    const double azimuth = std::numbers::pi * unit(rng);
    const double elevation = 0.26 * unit(rng);
    const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth),
                              std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    scan.rays.push_back({origin, origin + dir * (20.0 * std::abs(unit(rng)))});
  }
  CellMarks boxed;
  CellMarks hashed(false);
  for (const double resolution : {0.2, 0.1}) {
    const auto want = marked(hashed, scan, resolution);
    ASSERT_EQ(marked(boxed, scan, resolution), want) << "resolution " << resolution;
    EXPECT_TRUE(boxed.lastScanBoxed());
  }
}

TEST(CellMarks, ABoxOverBudgetFallsBackToHashedBricks) {
  const Scan scan = gridScan(5, 500, 160, 0.25);  // about 80 cells across: 11 bricks a side
  CellMarks small(true, 64);
  ASSERT_EQ(marked(small, scan, 0.25), expected(scan, 0.25));
  EXPECT_FALSE(small.lastScanBoxed());
  // Then a scan that fits: the box again, and nothing left over from the hashed scan.
  const Scan near = gridScan(6, 200, 12, 0.25);
  ASSERT_EQ(marked(small, near, 0.25), expected(near, 0.25));
  EXPECT_EQ(small.lastScanBoxed(), CellMarks::boxAvailable());
}

TEST(CellMarks, AReusedBoxHoldsOnlyTheCurrentScan) {
  CellMarks marks;
  const Scan wide = gridScan(7, 800, 200, 0.25);
  const Scan narrow = gridScan(8, 100, 20, 0.25);
  ASSERT_EQ(marked(marks, wide, 0.25), expected(wide, 0.25));
  ASSERT_EQ(marked(marks, narrow, 0.25), expected(narrow, 0.25));
  ASSERT_EQ(marked(marks, wide, 0.25), expected(wide, 0.25));
  // A scan with no marks at all reads back empty.
  EXPECT_TRUE(marked(marks, Scan{}, 0.25).empty());
}

}  // namespace
}  // namespace ogf::fusion
