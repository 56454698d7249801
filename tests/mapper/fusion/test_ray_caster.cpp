// RayCaster (Amanatides & Woo traversal) against the brute-force reference and on the cases that break
// traversals: rays along axes, of zero length, on cell boundaries, through cell corners, at negative
// coordinates.
#include "ray_reference.hpp"

#include <ogf/fusion/ray_caster.hpp>

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace ogf::fusion {
namespace {

std::vector<CellKey> cast(const Eigen::Vector3d& o, const Eigen::Vector3d& e, double resolution) {
  std::vector<CellKey> cells;
  for (const CellKey c : RayCaster(o, e, resolution)) cells.push_back(c);
  return cells;
}

std::vector<CellKey> keys(std::initializer_list<std::array<std::int32_t, 3>> list) {
  std::vector<CellKey> out;
  for (const auto& k : list) out.push_back({k[0], k[1], k[2]});
  return out;
}

TEST(RayCaster, AxisAlignedRayYieldsEachCellAlongTheAxisOnce) {
  EXPECT_EQ(cast({0.5, 0.5, 0.5}, {4.5, 0.5, 0.5}, 1.0), keys({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}));
  EXPECT_EQ(cast({0.5, 0.5, 0.5}, {0.5, -2.5, 0.5}, 1.0), keys({{0, 0, 0}, {0, -1, 0}, {0, -2, 0}}));
  EXPECT_EQ(cast({0.1, 0.1, 0.7}, {0.1, 0.1, 0.1}, 0.2), keys({{0, 0, 3}, {0, 0, 2}, {0, 0, 1}}));
}

TEST(RayCaster, ZeroLengthRayYieldsNothing) {
  EXPECT_TRUE(cast({1.3, -2.7, 0.4}, {1.3, -2.7, 0.4}, 0.2).empty());
  EXPECT_TRUE(cast({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 1.0).empty());
}

TEST(RayCaster, RayInsideOneCellYieldsNothing) {
  EXPECT_TRUE(cast({0.1, 0.1, 0.1}, {0.9, 0.9, 0.9}, 1.0).empty());
}

TEST(RayCaster, FirstCellIsTheOriginCellAndEndCellIsLeftOut) {
  const RayCaster ray({-3.3, 2.1, 0.05}, {7.7, -1.2, 1.9}, 0.2);
  const std::vector<CellKey> cells = cast({-3.3, 2.1, 0.05}, {7.7, -1.2, 1.9}, 0.2);
  ASSERT_FALSE(cells.empty());
  EXPECT_EQ(cells.front(), cellKeyOf({-3.3, 2.1, 0.05}, 0.2));
  EXPECT_EQ(ray.originCell(), cells.front());
  EXPECT_EQ(ray.endCell(), cellKeyOf({7.7, -1.2, 1.9}, 0.2));
  EXPECT_EQ(std::count(cells.begin(), cells.end(), ray.endCell()), 0);
}

TEST(RayCaster, DiagonalThroughACornerUpwardSkipsTheSideCells) {
  // The segment meets (1,0) and (0,1) in no point of their half-open boxes.
  EXPECT_EQ(cast({0.5, 0.5, 0.5}, {2.5, 2.5, 0.5}, 1.0), keys({{0, 0, 0}, {1, 1, 0}}));
  EXPECT_EQ(cast({0.5, 0.5, 0.5}, {2.5, 2.5, 2.5}, 1.0), keys({{0, 0, 0}, {1, 1, 1}}));
}

TEST(RayCaster, DiagonalThroughACornerDownwardSkipsTheSideCells) {
  EXPECT_EQ(cast({1.5, 1.5, 0.5}, {-0.5, -0.5, 0.5}, 1.0), keys({{1, 1, 0}, {0, 0, 0}}));
}

TEST(RayCaster, MixedDiagonalThroughACornerVisitsTheCornerCell) {
  // Going +x, -y through the corner (1, 1): the corner point itself lies in cell (1, 1), and only it.
  EXPECT_EQ(cast({0.5, 1.5, 0.5}, {1.5, 0.5, 0.5}, 1.0), keys({{0, 1, 0}, {1, 1, 0}}));
  // Two such corners, (1, 1) and (2, 0).
  EXPECT_EQ(cast({0.5, 1.5, 0.5}, {2.5, -0.5, 0.5}, 1.0), keys({{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0}}));
}

TEST(RayCaster, RayStartingOnABoundaryGoingDownYieldsTheOriginCellFirst) {
  EXPECT_EQ(cast({1.0, 0.5, 0.5}, {-0.5, 0.5, 0.5}, 1.0), keys({{1, 0, 0}, {0, 0, 0}}));
}

TEST(RayCaster, RayEndingOnABoundaryStopsBeforeTheCellItTouches) {
  EXPECT_EQ(cast({0.5, 0.5, 0.5}, {2.0, 0.5, 0.5}, 1.0), keys({{0, 0, 0}, {1, 0, 0}}));
  // Going down onto x = 1: the endpoint's cell is (1,0,0), so nothing is left after the origin's.
  EXPECT_TRUE(cast({1.5, 0.5, 0.5}, {1.0, 0.5, 0.5}, 1.0).empty());
}

TEST(RayCaster, NegativeCoordinatesHaveNoSeamAtZero) {
  EXPECT_EQ(cast({-0.3, 0.1, 0.1}, {0.5, 0.1, 0.1}, 0.2), keys({{-2, 0, 0}, {-1, 0, 0}, {0, 0, 0}, {1, 0, 0}}));
}

TEST(RayCaster, MaxCellsBoundsTheCellsYielded) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coord(-20.0, 20.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d o(coord(rng), coord(rng), coord(rng));
    const Eigen::Vector3d e(coord(rng), coord(rng), coord(rng));
    const RayCaster ray(o, e, 0.2);
    EXPECT_LE(static_cast<std::int64_t>(cast(o, e, 0.2).size()), ray.maxCells());
  }
}

// Random rays against the reference. Dyadic rays (coordinates on a 1/q-cell grid, power-of-two
// resolution) hit boundaries, edges and corners often and exactly; real rays at 0.2 m and 0.1 m test
// general position, far from the origin and at negative coordinates.
struct RandomRays {
  int dimensions;       // 2: z fixed inside one cell; 3: free
  int grid;             // 0: real coordinates; else 1/grid-cell grid
  double resolution;
  double half_width;    // metres
  Eigen::Vector3d centre;
};

class RayCasterAgainstReference : public ::testing::TestWithParam<RandomRays> {};

TEST_P(RayCasterAgainstReference, MatchesBruteForceOnRandomRays) {
  const RandomRays p = GetParam();
  std::mt19937_64 rng(static_cast<std::uint64_t>(p.dimensions * 1000 + p.grid) ^ std::uint64_t{0x5eed});
  std::uniform_real_distribution<double> real(-p.half_width, p.half_width);
  const int cells = static_cast<int>(p.half_width / p.resolution);
  std::uniform_int_distribution<int> ticks(-cells * p.grid, cells * p.grid);
  auto coordinate = [&]() {
    if (p.grid == 0) return real(rng);
    return static_cast<double>(ticks(rng)) / static_cast<double>(p.grid) * p.resolution;
  };
  int rays_with_ties = 0;
  for (int i = 0; i < 3000; ++i) {
    Eigen::Vector3d o(coordinate(), coordinate(), coordinate());
    Eigen::Vector3d e(coordinate(), coordinate(), coordinate());
    if (i % 10 == 0) e = o;                                   // zero length
    if (i % 10 == 1) e.y() = o.y(), e.z() = o.z();           // along x
    if (i % 10 == 2) e.x() = o.x(), e.y() = o.y();           // along z
    if (p.dimensions == 2) e.z() = o.z();
    o += p.centre;
    e += p.centre;
    const std::vector<CellKey> got = cast(o, e, p.resolution);
    const std::vector<CellKey> want = test::referenceRayCells(o, e, p.resolution);
    ASSERT_EQ(got, want) << "ray " << i << " from " << o.transpose() << " to " << e.transpose();
    const std::set<CellKey> unique(got.begin(), got.end());
    ASSERT_EQ(unique.size(), got.size()) << "a cell came twice";
    const RayCaster ray(o, e, p.resolution);
    if (static_cast<std::int64_t>(got.size()) < ray.maxCells()) ++rays_with_ties;
  }
  if (p.grid != 0 && p.grid <= 4) {
    EXPECT_GT(rays_with_ties, 0) << "the coarse grid should produce corner ties";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rays, RayCasterAgainstReference,
    ::testing::Values(RandomRays{2, 2, 1.0, 6.0, {0, 0, 0}}, RandomRays{3, 2, 1.0, 6.0, {0, 0, 0}},
                      RandomRays{2, 4, 0.5, 4.0, {-3.0, 2.0, 0.25}}, RandomRays{3, 4, 0.25, 2.0, {-1.0, -1.0, -1.0}},
                      RandomRays{3, 16, 0.5, 5.0, {0, 0, 0}}, RandomRays{2, 16, 1.0, 8.0, {-16, 8, -4}},
                      RandomRays{3, 0, 0.2, 6.0, {-100.3, 40.1, -2.7}}, RandomRays{2, 0, 0.2, 6.0, {0, 0, 0}},
                      RandomRays{3, 0, 0.1, 3.0, {12.34, -56.78, 0.9}}),
    [](const ::testing::TestParamInfo<RandomRays>& rays) {
      return std::to_string(rays.param.dimensions) + "d_grid" + std::to_string(rays.param.grid) + "_case" +
             std::to_string(rays.index);
    });

}  // namespace
}  // namespace ogf::fusion
