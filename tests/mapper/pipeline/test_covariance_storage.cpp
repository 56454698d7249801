// Compact covariance storage (the mapping programs' default) against the banded filter on the same scans:
// the classes a user sees agree within the stated bound, the memory is a sixth, and memoryBytes() is what
// the process really holds.
#include <gtest/gtest.h>

#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <cstdint>
#include <vector>

#include "ogf/filter/map_file.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "support/process_memory.hpp"

namespace {

using namespace ogf;

// A room seen by a 16-ring fan: walls at x = ±halfX and y = ±halfY, a floor 1.5 m below the sensor and a
// pillar, each ray ending at the first surface it meets.
struct RoomScan {
  std::vector<float> x, y, z;
  std::vector<std::int32_t> t;
  RoomScan(double halfX, double halfY) {
    for (int ring = 0; ring < 16; ++ring) {
      const double elev = (-15.0 + 2.0 * ring) * M_PI / 180.0;
      for (int a = 0; a < 900; ++a) {
        const double az = 0.4 * a * M_PI / 180.0;
        const double dx = std::cos(elev) * std::cos(az), dy = std::cos(elev) * std::sin(az), dz = std::sin(elev);
        double r = 100.0;
        const auto hit = [&](double d, double to) {
          if (d * to > 0.0) r = std::min(r, to / d);
        };
        hit(dx, halfX);
        hit(dx, -halfX);
        hit(dy, halfY);
        hit(dy, -halfY);
        hit(dz, -1.5);
        // The pillar: a 0.6 m square column around (2.5, 1.5).
        for (double along = 0.0; along < r; along += 0.02) {
          if (std::abs(along * dx - 2.5) < 0.3 && std::abs(along * dy - 1.5) < 0.3) {
            r = along;
            break;
          }
        }
        x.push_back(static_cast<float>(r * dx));
        y.push_back(static_cast<float>(r * dy));
        z.push_back(static_cast<float>(r * dz));
        t.push_back(a * 100);
      }
    }
  }
  fusion::ScanPoints points(std::int64_t start) const { return {start, x, y, z, t}; }
};

pipeline::ScanMapper makeMapper(filter::CovarianceStorage storage) {
  pipeline::MapperConfig c;
  c.setResolution(0.2);
  c.fusion.measurement.min_range_m = 0.1;
  c.fusion.measurement.max_range_m = 30.0;
  c.filter.covariance = storage;
  auto mapper = pipeline::ScanMapper::create(c);
  EXPECT_TRUE(mapper.ok());
  return std::move(mapper).value();
}

// Scans [first, last) of a drive along x through the room: 0.1 m a scan in a small room, 1 m in a large one.
void drive(pipeline::ScanMapper& mapper, const RoomScan& scan, int first, int last, double step) {
  for (int i = first; i < last; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = -1.0 + step * i;
    mapper.measureStatic(scan.points(i * 100000), pose);
    mapper.apply(mapper.measurements());
  }
}

pipeline::ScanMapper mapRoom(filter::CovarianceStorage storage, int scans) {
  pipeline::ScanMapper mapper = makeMapper(storage);
  drive(mapper, RoomScan(6.0, 4.0), 0, scans, 0.1);
  return mapper;
}

TEST(CovarianceStorage, CompactAndBandedMapsOfTheSameScansShowTheSameClasses) {
  const pipeline::ScanMapper banded = mapRoom(filter::CovarianceStorage::kBanded, 20);
  const pipeline::ScanMapper compact = mapRoom(filter::CovarianceStorage::kCompact, 20);
  EXPECT_EQ(compact.filter().config().covariance, filter::CovarianceStorage::kCompact);
  std::size_t cells = 0, same = 0, occupiedBanded = 0, occupiedBoth = 0;
  banded.filter().forEachCell([&](const CellKey& key, float mean, float) {
    const int b = filter::occupancyClass(static_cast<double>(mean), 0.65, 0.35);
    const int c = filter::occupancyClass(compact.filter().estimate(key).mean, 0.65, 0.35);
    ++cells;
    same += b == c ? 1U : 0U;
    occupiedBanded += b == 1 ? 1U : 0U;
    occupiedBoth += b == 1 && c == 1 ? 1U : 0U;
  });
  ASSERT_GT(occupiedBanded, 1000U);
  const double agreement = static_cast<double>(same) / static_cast<double>(cells);
  const double occupiedKept = static_cast<double>(occupiedBoth) / static_cast<double>(occupiedBanded);
  std::cout << "classes agree on " << agreement << " of " << cells << " cells; " << occupiedKept
            << " of the banded map's occupied cells occupied in the compact one\n";
  EXPECT_GE(agreement, 0.98);
  EXPECT_GE(occupiedKept, 0.995);
  // Same blocks; a sixth of the bytes (9 of 57 bytes a cell, 7 of them stored per cell).
  EXPECT_EQ(compact.filter().allocatedCells(), banded.filter().allocatedCells());
  EXPECT_LT(compact.filter().memoryBytes() * 6, banded.filter().memoryBytes());
}

// A mapper configured for compact storage restores a banded map by converting it (an older state
// directory); compact to banded and back is bit for bit the same map.
TEST(CovarianceStorage, SavedMapsAreConvertedToTheConfiguredStorage) {
  const pipeline::ScanMapper banded = mapRoom(filter::CovarianceStorage::kBanded, 5);
  pipeline::ScanMapper restored = makeMapper(filter::CovarianceStorage::kCompact);
  ASSERT_TRUE(restored.restoreFilter(filter::encodeMap(banded.filter()), "banded.map").ok());
  EXPECT_EQ(restored.filter().config().covariance, filter::CovarianceStorage::kCompact);
  EXPECT_EQ(restored.filter().blockKeys(), banded.filter().blockKeys());
  std::size_t differ = 0;
  banded.filter().forEachCell([&](const CellKey& key, float mean, float variance) {
    const auto e = restored.filter().estimate(key);
    differ += e.mean != static_cast<double>(mean) ? 1U : 0U;
    differ += std::abs(e.variance - static_cast<double>(variance)) > 2.5e-4 * static_cast<double>(variance) ? 1U : 0U;
  });
  EXPECT_EQ(differ, 0U) << "means kept exactly, variances to the 16-bit code's rounding";

  const filter::BandedOgf back = restored.filter()
                                     .withCovarianceStorage(filter::CovarianceStorage::kBanded)
                                     .withCovarianceStorage(filter::CovarianceStorage::kCompact);
  EXPECT_EQ(back.checksum(), restored.filter().checksum());
}

TEST(CovarianceStorage, MemoryBytesIsWhatTheProcessHolds) {
  // A 60 m x 40 m hall, driven through 1 m a scan. The first scans also size the mapper's per-scan scratch
  // (measurement set, batch tables), which memoryBytes() does not count: the comparison starts after them.
  const RoomScan hall(30.0, 20.0);
  pipeline::ScanMapper mapper = makeMapper(filter::CovarianceStorage::kCompact);
  drive(mapper, hall, 0, 5, 1.0);
  ::malloc_trim(0);  // what was freed goes back to the system, so the growth is the map's
  const auto before = ogf::testing::residentBytes(::getpid());
  const std::size_t countedBefore = mapper.filter().memoryBytes();
  drive(mapper, hall, 5, 35, 1.0);
  const auto after = ogf::testing::residentBytes(::getpid());
  ASSERT_TRUE(before.has_value() && after.has_value());
  const double grown = static_cast<double>(*after - *before);
  const double counted = static_cast<double>(mapper.filter().memoryBytes() - countedBefore);
  std::cout << "memoryBytes grew " << counted / 1e6 << " MB, the resident set " << grown / 1e6 << " MB\n";
  ASSERT_GT(counted, 10e6) << "too small a growth to compare with the resident set";
  // malloc's headers and the scratch of larger scans are not counted: memoryBytes() is within 20 % below.
  EXPECT_LE(counted, grown * 1.05);
  EXPECT_GE(counted, grown * 0.8);
}

}  // namespace
