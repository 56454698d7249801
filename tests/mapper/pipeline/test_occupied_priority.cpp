// The occupied-priority policy (FilterConfig::occupiedPriority, Sun et al. Sec. VI-B) on hand-built rays:
// a noisy wall keeps its cells under `map` and loses many under `scan`; a cell measured free after a hit
// takes the free measurement or not exactly as the configured policy says, in 3-D and 2-D maps.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/fusion/measurement_set.hpp"

namespace ogf::filter {
namespace {

constexpr double kResolution = 0.05;
constexpr double kWallX = 3.02;       // inside cell x = 60, 2 cm from its near face
constexpr double kRangeNoise = 0.03;  // σ of the return's range, the VLP-16's ±3 cm
constexpr int kScans = 50;

BandedOgf makeFilter(OccupiedPriority priority, int release = 20, int dimensions = 3) {
  FilterConfig config;
  config.dimensions = dimensions;
  config.resolution = dimensions == 3 ? kResolution : 1.0;
  config.occupiedPriority = priority;
  config.freeReleaseCount = release;
  auto made = BandedOgf::create(config);
  EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().message);
  return std::move(made).value();
}

struct WallShares {
  double wallOccupied = 0.0;  // wall cells (x = 60) classed occupied
  double airFree = 0.0;       // cells on the way to the wall cells, 12–40 cm in front of the wall, classed free
};

// A sensor at the origin sees the patch y ∈ [3, 4), z ∈ [-0.25, 0.25) of the wall x = kWallX obliquely (45° to
// 53° from its normal, so a ray crosses one or two cells of the wall's layer before it ends), one ray per
// wall cell and scan on average, at random points, each range perturbed by N(0, kRangeNoise²).
WallShares mapNoisyWall(OccupiedPriority priority) {
  BandedOgf filter = makeFilter(priority);
  fusion::MeasurementConfig mc;
  mc.resolution_m = kResolution;
  fusion::MeasurementSet set(mc);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uy(3.0, 4.0);
  std::uniform_real_distribution<double> uz(-0.25, 0.25);
  std::normal_distribution<double> noise(0.0, kRangeNoise);
  const int cellsY = 20;
  const int cellsZ = 10;
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (int scan = 0; scan < kScans; ++scan) {
    set.begin();
    for (int i = 0; i < cellsY * cellsZ; ++i) {
      const Eigen::Vector3d onWall(kWallX, uy(rng), uz(rng));
      const double range = onWall.norm();
      set.addReturn(origin, onWall * ((range + noise(rng)) / range));
    }
    filter.update(set.finish());
  }
  const FilterConfig& c = filter.config();
  auto classOf = [&](const CellKey& k) {
    return occupancyClass(filter.estimate(k).mean, c.occupiedThreshold, c.freeThreshold);
  };
  WallShares shares;
  int wall = 0;
  int air = 0;
  int airCells = 0;
  // Cells inside the patch, one row of cells away from its edges (rays near an edge may land outside); the
  // air on the way to each, 12 to 40 cm in front of the wall (4σ and more, as a return is rarely that short).
  for (int y = 60 + 1; y < 60 + cellsY - 1; ++y) {
    for (int z = -cellsZ / 2 + 1; z < cellsZ / 2 - 1; ++z) {
      wall += classOf(CellKey{60, y, z}) == 1 ? 1 : 0;
      const Eigen::Vector3d centre = (Eigen::Vector3d(60, y, z) + Eigen::Vector3d::Constant(0.5)) * kResolution;
      for (const double inFront : {0.12, 0.2, 0.3, 0.4}) {
        const Eigen::Vector3d p = centre * (1.0 - inFront / centre.x());
        air += classOf(cellKeyOf(p, kResolution)) == -1 ? 1 : 0;
        ++airCells;
      }
    }
  }
  shares.wallOccupied = static_cast<double>(wall) / ((cellsY - 2) * (cellsZ - 2));
  shares.airFree = static_cast<double>(air) / airCells;
  return shares;
}

TEST(OccupiedPriority, NoisyWallSeenFiftyTimesStaysOccupiedUnderTheMapPolicy) {
  const WallShares map = mapNoisyWall(OccupiedPriority::kMap);
  const WallShares scan = mapNoisyWall(OccupiedPriority::kScan);
  SCOPED_TRACE("wall occupied: map " + std::to_string(map.wallOccupied) + ", scan " +
               std::to_string(scan.wallOccupied) + "; air free: map " + std::to_string(map.airFree) +
               ", scan " + std::to_string(scan.airFree));
  EXPECT_GE(map.wallOccupied, 0.95);
  // Rays ending in the cell behind the wall cross it: under `scan` their free measurements outvote the hits.
  EXPECT_LT(scan.wallOccupied, map.wallOccupied - 0.1);
  // The air in front stays free under both.
  EXPECT_GE(map.airFree, 0.99);
  EXPECT_GE(scan.airFree, 0.99);
}

// One cell hit once, then measured free in `frees` batches of its own; returns the mean after each batch
// and the held-back count of each.
struct FreeRun {
  std::vector<double> means;  // means[0] after the hit, means[i] after the i-th free batch
  std::vector<std::size_t> heldBack;
};

FreeRun hitThenFree(BandedOgf& filter, const CellKey& cell, int frees) {
  FreeRun run;
  const Measurement hit{cell, Measurement::kOccupied};
  filter.update(std::span<const Measurement>(&hit, 1));
  run.means.push_back(filter.estimate(cell).mean);
  const Measurement free{cell, Measurement::kFree};
  for (int i = 0; i < frees; ++i) {
    run.heldBack.push_back(filter.update(std::span<const Measurement>(&free, 1)).heldBack);
    run.means.push_back(filter.estimate(cell).mean);
  }
  return run;
}

class FreeAfterHit : public testing::TestWithParam<int> {};

TEST_P(FreeAfterHit, ScanPolicyTakesEveryFreeMeasurement) {
  BandedOgf filter = makeFilter(OccupiedPriority::kScan, 20, GetParam());
  const FreeRun run = hitThenFree(filter, CellKey{3, 4, 0}, 5);
  for (std::size_t i = 1; i < run.means.size(); ++i) {
    EXPECT_LT(run.means[i], run.means[i - 1]) << "free batch " << i;
    EXPECT_EQ(run.heldBack[i - 1], 0U);
  }
}

TEST_P(FreeAfterHit, MapPolicyWithoutReleaseNeverTakesAFreeMeasurement) {
  BandedOgf filter = makeFilter(OccupiedPriority::kMap, 0, GetParam());
  const FreeRun run = hitThenFree(filter, CellKey{3, 4, 0}, 200);  // beyond the 7-bit count
  EXPECT_GT(run.means[0], 0.0);
  for (std::size_t i = 1; i < run.means.size(); ++i) {
    ASSERT_EQ(run.means[i], run.means[0]) << "free batch " << i;
    ASSERT_EQ(run.heldBack[i - 1], 1U);
  }
}

TEST_P(FreeAfterHit, MapPolicyReleasesAfterTheConfiguredRunOfFreeScans) {
  constexpr std::size_t kRelease = 4;
  BandedOgf filter = makeFilter(OccupiedPriority::kMap, static_cast<int>(kRelease), GetParam());
  const CellKey cell{3, 4, 0};
  FreeRun run = hitThenFree(filter, cell, 6);
  for (std::size_t i = 1; i < kRelease; ++i) {  // the first kRelease − 1 free scans are held back
    EXPECT_EQ(run.means[i], run.means[0]) << "free batch " << i;
    EXPECT_EQ(run.heldBack[i - 1], 1U);
  }
  for (std::size_t i = kRelease; i <= 6; ++i) {  // then every free measurement applies
    EXPECT_LT(run.means[i], run.means[i - 1]) << "free batch " << i;
    EXPECT_EQ(run.heldBack[i - 1], 0U);
  }
  // A new hit arms the cell again; a hit in the middle of a run of frees restarts the count.
  run = hitThenFree(filter, cell, 2);
  EXPECT_EQ(run.means[2], run.means[0]);
  run = hitThenFree(filter, cell, static_cast<int>(kRelease) - 1);
  EXPECT_EQ(run.means.back(), run.means[0]);
}

TEST_P(FreeAfterHit, NeighboursOfAHitCellStillTakeFreeMeasurements) {
  BandedOgf filter = makeFilter(OccupiedPriority::kMap, 0, GetParam());
  const CellKey cell{3, 4, 0};
  const Measurement hit{cell, Measurement::kOccupied};
  filter.update(std::span<const Measurement>(&hit, 1));
  const CellKey neighbour{4, 4, 0};
  const double before = filter.estimate(neighbour).mean;
  const Measurement free{neighbour, Measurement::kFree};
  EXPECT_EQ(filter.update(std::span<const Measurement>(&free, 1)).heldBack, 0U);
  EXPECT_LT(filter.estimate(neighbour).mean, before);
}

// A hit and a free measurement of the same never-hit cell in one batch: the marks from before the batch
// decide, so both reach the filter, in either order.
TEST_P(FreeAfterHit, MarksFromBeforeTheBatchDecide) {
  BandedOgf a = makeFilter(OccupiedPriority::kMap, 0, GetParam());
  BandedOgf b = makeFilter(OccupiedPriority::kMap, 0, GetParam());
  const std::vector<Measurement> hitFirst{{CellKey{3, 4, 0}, Measurement::kOccupied},
                                          {CellKey{3, 4, 0}, Measurement::kFree}};
  const std::vector<Measurement> freeFirst{hitFirst[1], hitFirst[0]};
  EXPECT_EQ(a.update(hitFirst).heldBack, 0U);
  EXPECT_EQ(b.update(freeFirst).heldBack, 0U);
  // The next free batch is held back in both.
  const Measurement free{CellKey{3, 4, 0}, Measurement::kFree};
  EXPECT_EQ(a.update(std::span<const Measurement>(&free, 1)).heldBack, 1U);
  EXPECT_EQ(b.update(std::span<const Measurement>(&free, 1)).heldBack, 1U);
}

INSTANTIATE_TEST_SUITE_P(Dimensions, FreeAfterHit, testing::Values(3, 2),
                         [](const testing::TestParamInfo<int>& param) {
                           return std::to_string(param.param) + "D";
                         });

}  // namespace
}  // namespace ogf::filter
