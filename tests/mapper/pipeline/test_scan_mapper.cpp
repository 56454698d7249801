// The pipeline on a scene with a known answer: a static sensor facing a wall maps the wall occupied and
// the air in front of it free; replaying the measurement sets (as the journal does) rebuilds the same map
// bit for bit; and the delta candidates it reports are exactly the cells whose published state changed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/filter/map_file.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/pipeline/published_cells.hpp"
#include "ogf/pipeline/scan_mapper.hpp"

namespace {

using namespace ogf;

// A fan of rays from the origin hitting the plane x = wall_x, 16 rings x 200 azimuths.
struct WallScan {
  std::vector<float> x, y, z;
  std::vector<std::int32_t> t;
  explicit WallScan(double wall_x) {
    for (int ring = 0; ring < 16; ++ring) {
      const double elev = (-15.0 + 2.0 * ring) * M_PI / 180.0;
      for (int a = 0; a < 200; ++a) {
        const double az = (-30.0 + 0.3 * a) * M_PI / 180.0;
        const double dir_x = std::cos(elev) * std::cos(az);
        const double r = wall_x / dir_x;
        x.push_back(static_cast<float>(r * dir_x));
        y.push_back(static_cast<float>(r * std::cos(elev) * std::sin(az)));
        z.push_back(static_cast<float>(r * std::sin(elev)));
        t.push_back(a * 1000);
      }
    }
  }
  fusion::ScanPoints points(std::int64_t start) const { return {start, x, y, z, t}; }
};

pipeline::MapperConfig config() {
  pipeline::MapperConfig c;
  c.setResolution(0.2);
  c.fusion.measurement.min_range_m = 0.1;
  c.fusion.measurement.max_range_m = 30.0;
  return c;
}

TEST(ScanMapper, StaticSensorMapsTheWallOccupiedAndTheAirBeforeItFree) {
  auto mapper = pipeline::ScanMapper::create(config());
  ASSERT_TRUE(mapper.ok()) << mapper.error().message;
  const WallScan scan(4.1);  // the wall lies inside the cell column x in [4.0, 4.2)
  for (int i = 0; i < 5; ++i) {
    mapper->measureStatic(scan.points(i * 100000), Eigen::Isometry3d::Identity());
    ASSERT_FALSE(mapper->measurements().empty());
    mapper->apply(mapper->measurements());
  }
  const auto& f = mapper->filter();
  const auto cls = [&](int ix, int iy, int iz) {
    const auto e = f.estimate({ix, iy, iz});
    return filter::occupancyClass(e.mean, 0.65, 0.35);
  };
  EXPECT_EQ(cls(20, 0, 0), 1);   // the wall, straight ahead
  EXPECT_EQ(cls(10, 0, 0), -1);  // 2 m of air before it
  EXPECT_EQ(cls(2, 0, 0), -1);
  EXPECT_EQ(cls(25, 0, 0), 0);   // behind the wall: never seen
}

TEST(ScanMapper, ReplayingTheMeasurementSetsRebuildsTheSameMapBitForBit) {
  auto live = pipeline::ScanMapper::create(config());
  auto replay = pipeline::ScanMapper::create(config());
  ASSERT_TRUE(live.ok() && replay.ok());
  std::vector<std::vector<Measurement>> journal;
  for (int i = 0; i < 4; ++i) {
    const WallScan scan(3.0 + 0.37 * i);
    live->measureStatic(scan.points(i), Eigen::Isometry3d(Eigen::Translation3d(0.05 * i, 0.0, 0.0)));
    journal.emplace_back(live->measurements().begin(), live->measurements().end());
    live->apply(live->measurements());
  }
  for (const auto& set : journal) replay->apply(set);
  EXPECT_EQ(live->filter().checksum(), replay->filter().checksum());
}

// A saved map brings its cells, not its policy: restored into a mapper configured with other clamps and
// thresholds, it filters as configured now (an older file, or a configuration changed since the save).
TEST(ScanMapper, RestoredMapTakesTheConfiguredClampsAndThresholds) {
  pipeline::MapperConfig saved_with = config();
  saved_with.filter.freeClampZ = 0.0;
  saved_with.filter.occupiedThreshold = 0.7;
  auto saver = pipeline::ScanMapper::create(saved_with);
  ASSERT_TRUE(saver.ok());
  const WallScan scan(4.1);
  saver->measureStatic(scan.points(0), Eigen::Isometry3d::Identity());
  saver->apply(saver->measurements());
  const std::vector<std::uint8_t> bytes = filter::encodeMap(saver->filter());

  pipeline::MapperConfig now = config();
  now.filter.freeClampZ = 1.25;
  auto restored = pipeline::ScanMapper::create(now);
  ASSERT_TRUE(restored.ok());
  ASSERT_TRUE(restored->restoreFilter(bytes, "saved").ok());
  EXPECT_EQ(restored->filter().config().freeClampZ, 1.25);
  EXPECT_EQ(restored->filter().config().occupiedThreshold, 0.65);
  EXPECT_EQ(restored->filter().checksum(), saver->filter().checksum()) << "the cells are the saved ones";

  // A configuration the saved map cannot take is refused and the mapper keeps its own filter.
  pipeline::MapperConfig other = config();
  other.setResolution(0.25);
  auto refused = pipeline::ScanMapper::create(other);
  ASSERT_TRUE(refused.ok());
  const auto st = refused->restoreFilter(bytes, "saved");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("resolution"), std::string::npos) << st.error().message;

  // So is another stencil: the map would go on filtering with the one it was made with.
  pipeline::MapperConfig ball = config();
  ball.filter.stencilManhattanRadius = 0;
  auto refusedStencil = pipeline::ScanMapper::create(ball);
  ASSERT_TRUE(refusedStencil.ok());
  const auto stencil = refusedStencil->restoreFilter(bytes, "saved");
  ASSERT_FALSE(stencil.ok());
  EXPECT_NE(stencil.error().message.find("saved: stencil Manhattan radius 2"), std::string::npos)
      << stencil.error().message;
  EXPECT_EQ(refusedStencil->filter().config().stencilManhattanRadius, 0);
}

// Every cell of the filter has in the stream's published map the probability and class the filter gives it.
void expectEveryCellPublishedAsTheFilterHoldsIt(const pipeline::ScanMapper& mapper, const delta::DeltaStream& stream) {
  std::size_t compared = 0;
  for (const auto& now : mapper.publishedCells()) {
    const delta::PublishedCell published = stream.map().find(now.key).value_or(delta::PublishedCell{now.key});
    ASSERT_EQ(published.probability, now.probability) << now.key.x << "," << now.key.y << "," << now.key.z;
    ASSERT_EQ(published.cell_class, now.cell_class);
    ++compared;
  }
  EXPECT_GT(compared, 1000u);
}

TEST(ScanMapper, DeltaCandidatesKeepEveryCellsVisibleStateUpToDate) {
  // Publishing each scan's candidates must leave every cell with the probability and class the filter
  // gives it now. (Variance alone is never news, and a cell that drifts back to the prior stays in the
  // stream with the prior's state, so compare the visible state, not the checksum.)
  auto mapper = pipeline::ScanMapper::create(config());
  ASSERT_TRUE(mapper.ok());
  delta::DeltaStream stream({0.2, 1, 3300});
  pipeline::ChangedCells changes;
  for (int i = 0; i < 4; ++i) {
    const WallScan scan(2.5 + 0.5 * i);
    mapper->measureStatic(scan.points(i), Eigen::Isometry3d::Identity());
    changes.clear();
    mapper->apply(mapper->measurements(), &changes);
    EXPECT_FALSE(changes.empty());
    stream.update(i, changes);
  }
  expectEveryCellPublishedAsTheFilterHoldsIt(*mapper, stream);
}

TEST(ScanMapper, StaleSlabsReadAgainFromTheFilterBringThePublishedMapUpToDate) {
  // The same scans through a stream whose budget carries a fraction of their changes and whose waiting set
  // holds few of them: most changes leave only their slab marked, and reading those slabs from the filter
  // (refreshStaleSlabs, as ogf-mapper does after each scan) must still end with every cell's visible state.
  auto mapper = pipeline::ScanMapper::create(config());
  ASSERT_TRUE(mapper.ok());
  delta::DeltaStream stream({0.2, 1, 100}, delta::PublishingRule{0.0, 0.0});
  stream.limitWaiting(500);
  pipeline::ChangedCells changes;
  std::size_t most_stale = 0;
  int update = 0;
  for (; update < 4; ++update) {
    const WallScan scan(2.5 + 0.5 * update);
    mapper->measureStatic(scan.points(update), Eigen::Isometry3d::Identity());
    changes.clear();
    mapper->apply(mapper->measurements(), &changes);
    pipeline::refreshStaleSlabs(mapper->filter(), stream);
    stream.allow(delta::DeltaStream::partBytes(100) * 3);
    stream.update(update, changes);
    EXPECT_LE(stream.deferred().size(), 500u);
    most_stale = std::max(most_stale, stream.stale().size());
  }
  EXPECT_GT(most_stale, 10u) << "the scans' changes should have overflowed the waiting cells";
  for (; (!stream.deferred().empty() || !stream.stale().empty()) && update < 10000; ++update) {
    pipeline::refreshStaleSlabs(mapper->filter(), stream);
    stream.allow(delta::DeltaStream::partBytes(100) * 3);
    stream.update(update, std::vector<delta::PublishedCell>{});
  }
  ASSERT_TRUE(stream.deferred().empty());
  ASSERT_TRUE(stream.stale().empty());
  expectEveryCellPublishedAsTheFilterHoldsIt(*mapper, stream);
}

TEST(MapperConfig, RefusesDisagreeingCellSizesNamingTheField) {
  auto c = config();
  c.filter.resolution = 0.1;
  const auto st = c.validate();
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().message.find("filter.resolution"), std::string::npos);
}

}  // namespace
