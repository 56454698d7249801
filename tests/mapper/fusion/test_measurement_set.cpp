// MeasurementSet: the per-scan rules of Sun et al. Sec. VI-B (free along the ray, occupied end cell, one
// measurement per cell with occupied winning, max range cut, min range ignored, optional no-return free
// space), checked against a std::map reference, plus order independence, buffer reuse and grazing rays.
#include "ray_reference.hpp"

#include <ogf/fusion/measurement_set.hpp>
#include <ogf/fusion/ray_caster.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <vector>

namespace ogf::fusion {
namespace {

MeasurementConfig config(double resolution = 0.2, double min_range = 0.5, double max_range = 10.0) {
  MeasurementConfig c;
  c.resolution_m = resolution;
  c.min_range_m = min_range;
  c.max_range_m = max_range;
  return c;
}

std::vector<Measurement> copy(std::span<const Measurement> m) { return {m.begin(), m.end()}; }

// The rules written the slow, obvious way.
std::vector<Measurement> referenceSet(const MeasurementConfig& c, const std::vector<Eigen::Vector3d>& origins,
                                      const std::vector<Eigen::Vector3d>& endpoints) {
  std::map<CellKey, std::int8_t, BrickOrder> cells;
  auto mark = [&](const CellKey& k, std::int8_t y) {
    auto [it, inserted] = cells.emplace(k, y);
    if (!inserted) it->second = std::max(it->second, y);
  };
  for (std::size_t i = 0; i < origins.size(); ++i) {
    const Eigen::Vector3d ray = endpoints[i] - origins[i];
    const double range = ray.norm();
    if (range < c.min_range_m) continue;
    const bool cut = range > c.max_range_m;
    const Eigen::Vector3d end = cut ? Eigen::Vector3d(origins[i] + ray * (c.max_range_m / range)) : endpoints[i];
    for (const CellKey k : RayCaster(origins[i], end, c.resolution_m)) mark(k, Measurement::kFree);
    if (!cut) mark(cellKeyOf(end, c.resolution_m), Measurement::kOccupied);
  }
  std::vector<Measurement> out;
  for (const auto& [k, y] : cells) out.push_back({k, y});
  return out;
}

struct RandomScan {
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
};

RandomScan randomScan(std::uint64_t seed, int rays, double reach) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> range(0.0, reach);
  RandomScan scan;
  // A sensor moving along a short path (each ray its own origin), rays in all directions.
  for (int i = 0; i < rays; ++i) {
    const Eigen::Vector3d origin(-3.1 + 0.001 * i, 2.05 - 0.0005 * i, 0.7);
    Eigen::Vector3d dir(unit(rng), unit(rng), 0.3 * unit(rng));
    dir.normalize();
    scan.origins.push_back(origin);
    scan.endpoints.push_back(origin + dir * range(rng));
  }
  return scan;
}

TEST(MeasurementSet, MatchesTheReferenceOnRandomScans) {
  for (const double resolution : {0.2, 0.1, 0.25}) {
    const MeasurementConfig c = config(resolution, 0.5, 8.0);
    MeasurementSet set(c);
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      const RandomScan scan = randomScan(seed, 2000, 12.0);
      const auto got = copy(set.build(scan.origins, scan.endpoints));
      const auto want = referenceSet(c, scan.origins, scan.endpoints);
      ASSERT_EQ(got, want) << "resolution " << resolution << " seed " << seed;
      EXPECT_GT(set.counts().cut_at_max_range, 0);
      EXPECT_GT(set.counts().ignored_min_range, 0);
      EXPECT_GT(set.counts().returns, 0);
    }
  }
}

// Rays between points of a quarter-cell grid cross cell edges and corners exactly, in every direction and
// across brick boundaries on both sides of zero: the set must hold exactly the cells of the brute-force
// traversal (ray_reference.hpp), ties included.
TEST(MeasurementSet, RaysThroughCellCornersMatchTheBruteForceCells) {
  const double resolution = 0.25;
  MeasurementConfig c = config(resolution, 0.0, 100.0);
  MeasurementSet set(c);
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int> quarter(-80, 80);  // ±20 cells: bricks on both sides of zero
  auto point = [&]() -> Eigen::Vector3d {
    const double x = quarter(rng), y = quarter(rng), z = quarter(rng);
    return Eigen::Vector3d(x, y, z) * (resolution / 4.0);
  };
  int rays_with_ties = 0;
  for (int scan = 0; scan < 20; ++scan) {
    std::vector<Eigen::Vector3d> origins;
    std::vector<Eigen::Vector3d> endpoints;
    std::map<CellKey, std::int8_t, BrickOrder> want;
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d o = point();
      Eigen::Vector3d e = point();
      if (i % 7 == 1) e.z() = o.z();  // in a plane of cell faces or inside one layer
      origins.push_back(o);
      endpoints.push_back(e);
      const std::vector<CellKey> cells = test::referenceRayCells(o, e, resolution);
      if (static_cast<std::int64_t>(cells.size()) < RayCaster(o, e, resolution).maxCells()) ++rays_with_ties;
      for (const CellKey& k : cells) want.emplace(k, Measurement::kFree);
    }
    for (const Eigen::Vector3d& e : endpoints) want[cellKeyOf(e, resolution)] = Measurement::kOccupied;
    std::vector<Measurement> expected;
    for (const auto& [k, y] : want) expected.push_back({k, y});
    ASSERT_EQ(copy(set.build(origins, endpoints)), expected) << "scan " << scan;
  }
  EXPECT_GT(rays_with_ties, 100) << "the grid should produce many edge and corner ties";
}

TEST(MeasurementSet, OutputIsInBrickOrderWithOneMeasurementPerCell) {
  MeasurementSet set(config());
  const RandomScan scan = randomScan(9, 3000, 9.0);
  const auto m = copy(set.build(scan.origins, scan.endpoints));
  ASSERT_FALSE(m.empty());
  for (std::size_t i = 1; i < m.size(); ++i) ASSERT_TRUE(BrickOrder{}(m[i - 1].key, m[i].key)) << "at " << i;
  // Brick order, not CellKey order: cells on both sides of a brick face interleave.
  EXPECT_FALSE(
      std::is_sorted(m.begin(), m.end(), [](const auto& a, const auto& b) { return a.key < b.key; }));
}

TEST(MeasurementSet, RayOrderDoesNotChangeTheResult) {
  MeasurementSet set(config());
  RandomScan scan = randomScan(4, 2000, 9.0);
  const auto first = copy(set.build(scan.origins, scan.endpoints));
  std::vector<std::size_t> perm(scan.origins.size());
  for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), std::mt19937_64(11));
  RandomScan shuffled;
  for (const std::size_t i : perm) {
    shuffled.origins.push_back(scan.origins[i]);
    shuffled.endpoints.push_back(scan.endpoints[i]);
  }
  EXPECT_EQ(copy(set.build(shuffled.origins, shuffled.endpoints)), first);
}

TEST(MeasurementSet, ReusedSetGivesTheSameResultAsAFreshOne) {
  MeasurementSet reused(config());
  const RandomScan a = randomScan(5, 1500, 9.0);
  const RandomScan b = randomScan(6, 300, 4.0);
  (void)reused.build(a.origins, a.endpoints);
  const auto second = copy(reused.build(b.origins, b.endpoints));
  MeasurementSet fresh(config());
  EXPECT_EQ(second, copy(fresh.build(b.origins, b.endpoints)));
}

TEST(MeasurementSet, SingleReturnIsFreeAlongTheRayAndOccupiedAtTheEnd) {
  MeasurementSet set(config(1.0, 0.5, 10.0));
  set.begin();
  set.addReturn({0.5, 0.5, 0.5}, {3.5, 0.5, 0.5});
  const auto m = copy(set.finish());
  const std::vector<Measurement> want{{{0, 0, 0}, Measurement::kFree},
                                      {{1, 0, 0}, Measurement::kFree},
                                      {{2, 0, 0}, Measurement::kFree},
                                      {{3, 0, 0}, Measurement::kOccupied}};
  EXPECT_EQ(m, want);
}

TEST(MeasurementSet, OccupiedWinsOverFreeForTheSameCellInEitherOrder) {
  for (const bool occupied_first : {true, false}) {
    MeasurementSet set(config(1.0, 0.5, 10.0));
    set.begin();
    if (occupied_first) set.addReturn({0.5, 0.5, 0.5}, {2.5, 0.5, 0.5});
    set.addReturn({0.5, 0.5, 0.5}, {5.5, 0.5, 0.5});  // passes through (2,0,0)
    if (!occupied_first) set.addReturn({0.5, 0.5, 0.5}, {2.5, 0.5, 0.5});
    const auto m = copy(set.finish());
    ASSERT_EQ(m.size(), 6U);
    EXPECT_EQ(m[2].key, (CellKey{2, 0, 0}));
    EXPECT_EQ(m[2].y, Measurement::kOccupied);
  }
}

TEST(MeasurementSet, ReturnBeyondMaxRangeGivesFreeCellsOnlyAndNoneBeyondMaxRange) {
  const double max_range = 5.0;
  MeasurementSet set(config(0.2, 0.5, max_range));
  set.begin();
  const Eigen::Vector3d origin(0.05, -0.13, 0.3);
  const Eigen::Vector3d endpoint = origin + Eigen::Vector3d(3.0, 4.0, 1.0).normalized() * 9.0;
  set.addReturn(origin, endpoint);
  const auto m = copy(set.finish());
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(set.counts().cut_at_max_range, 1);
  EXPECT_EQ(set.counts().returns, 0);
  const double half_diagonal = 0.2 * std::sqrt(3.0) / 2.0;
  for (const Measurement& x : m) {
    EXPECT_EQ(x.y, Measurement::kFree);
    EXPECT_LE((cellCentre(x.key, 0.2) - origin).norm(), max_range + half_diagonal);
  }
}

TEST(MeasurementSet, ReturnAtExactlyMaxRangeIsStillOccupied) {
  MeasurementSet set(config(1.0, 0.5, 3.0));
  set.begin();
  set.addReturn({0.5, 0.5, 0.5}, {3.5, 0.5, 0.5});
  const auto m = copy(set.finish());
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(m.back().y, Measurement::kOccupied);
}

TEST(MeasurementSet, ReturnCloserThanMinRangeIsIgnored) {
  MeasurementSet set(config(0.2, 1.0, 10.0));
  set.begin();
  set.addReturn({0.0, 0.0, 0.0}, {0.9, 0.0, 0.0});
  EXPECT_TRUE(set.finish().empty());
  EXPECT_EQ(set.counts().ignored_min_range, 1);
}

TEST(MeasurementSet, NonFiniteRaysAreCountedAndSkipped) {
  MeasurementSet set(config());
  set.begin();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  set.addReturn({0.0, 0.0, 0.0}, {nan, 1.0, 0.0});
  set.addReturn({inf, 0.0, 0.0}, {1.0, 1.0, 0.0});
  set.addNoReturn({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  EXPECT_TRUE(set.finish().empty());
  EXPECT_EQ(set.counts().rejected_non_finite, 3);
}

TEST(MeasurementSet, RaysBeyondTheCellKeyRangeAreCountedAndSkipped) {
  MeasurementSet set(config(0.2, 0.5, 10.0));
  set.begin();
  set.addReturn({1e9, 0.0, 0.0}, {1e9 + 1.0, 0.0, 0.0});  // 5e9 cells: beyond int32
  set.addReturn({0.0, 0.0, 0.0}, {0.0, -1e12, 0.0});
  EXPECT_TRUE(set.finish().empty());
  EXPECT_EQ(set.counts().rejected_out_of_range, 2);
}

TEST(MeasurementSet, NoReturnBeamsAreIgnoredByDefault) {
  MeasurementConfig c = config(0.2, 0.5, 5.0);
  EXPECT_FALSE(c.free_space_for_no_return);
  MeasurementSet set(c);
  set.begin();
  set.addNoReturn({0.0, 0.0, 0.0}, {1.0, 0.0, 0.0});
  EXPECT_TRUE(set.finish().empty());
  EXPECT_EQ(set.counts().no_return_ignored, 1);
}

TEST(MeasurementSet, NoReturnBeamsGiveFreeSpaceUpToMaxRangeWhenEnabled) {
  MeasurementConfig c = config(1.0, 0.5, 5.0);
  c.free_space_for_no_return = true;
  MeasurementSet set(c);
  set.begin();
  set.addNoReturn({0.5, 0.5, 0.5}, {2.0, 0.0, 0.0});
  const auto m = copy(set.finish());
  ASSERT_EQ(m.size(), 5U);  // cells 0..4; the cell holding the point at 5 m is left out
  for (std::size_t i = 0; i < m.size(); ++i) {
    EXPECT_EQ(m[i].key, (CellKey{static_cast<std::int32_t>(i), 0, 0}));
    EXPECT_EQ(m[i].y, Measurement::kFree);
  }
}

TEST(MeasurementSet, ThinFloorSurvivesAScanOfGrazingRays) {
  // A VLP-16-like sensor 0.8 m above a floor whose surface lies in the z = 0 layer of 0.2 m cells. Rings
  // from -15° to -1° hit the floor at shallow angles; each ray crosses floor cells that other rays hit
  // before it reaches its own return. Occupied wins within a scan, so every hit floor cell stays occupied.
  const double res = 0.2;
  MeasurementSet set(config(res, 0.5, 30.0));
  set.begin();
  const Eigen::Vector3d origin(0.1, 0.1, 0.9);
  std::map<CellKey, bool> hit;  // floor cells hit, and whether some other ray crosses them as free
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays;
  for (int ring = 0; ring < 8; ++ring) {
    const double elevation = (-15.0 + 2.0 * ring) * std::numbers::pi / 180.0;
    for (int a = 0; a < 1800; ++a) {
      const double azimuth = a * 0.2 * std::numbers::pi / 180.0;
      const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                std::sin(elevation));
      const double range = (0.1 - origin.z()) / dir.z();  // the floor surface at z = 0.1 m
      const Eigen::Vector3d endpoint = origin + dir * range;
      if (range > 30.0) continue;
      rays.emplace_back(origin, endpoint);
      set.addReturn(origin, endpoint);
      hit[cellKeyOf(endpoint, res)] = false;
    }
  }
  for (const auto& [o, e] : rays) {
    for (const CellKey k : RayCaster(o, e, res)) {
      if (auto it = hit.find(k); it != hit.end()) it->second = true;
    }
  }
  const auto crossed = std::count_if(hit.begin(), hit.end(), [](const auto& kv) { return kv.second; });
  ASSERT_GT(crossed, 100) << "the scene should have floor cells that other rays cross as free";
  const auto m = copy(set.finish());
  std::map<CellKey, std::int8_t> result;
  for (const Measurement& x : m) result[x.key] = x.y;
  for (const auto& [k, crossed_as_free] : hit) {
    ASSERT_EQ(result.at(k), Measurement::kOccupied) << "floor cell " << k.x << "," << k.y << "," << k.z;
  }
}

}  // namespace
}  // namespace ogf::fusion
