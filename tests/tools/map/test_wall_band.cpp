// The walls' band of the top-down pictures (map_io::wallBand, tools::WallBandFinder) on rooms built cell by
// cell as a lidar map holds them: walls standing from floor to ceiling, a floor and a ceiling with free cells
// where rays passed over or under them. The band starts right above the floor however little of it was seen,
// stays under the ceiling, fills a room lower than a band, keeps low obstacles and follows the map's frame;
// the --png-zmin/--png-zmax bounds override it. On the real capture (../shared), mapped through the library
// with and without an extrinsic, the band holds the walls the README's picture shows.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <utility>

#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/topdown_png.hpp"
#include "support/shared_data.hpp"

namespace {

using namespace ogf;
using Column = std::map<int, std::int8_t>;  // layer -> -1 free, 0 unknown, +1 occupied

constexpr double kRes = 0.1;

// A square room of side × side columns at 0.1 m, floor at layer `floor`, ceiling at layer `ceiling`: the
// border columns are walls, occupied from the floor to the ceiling; inside, the floor is occupied with free
// cells above it where `floor_seen`, the ceiling occupied with free cells below it where `ceiling_seen`.
struct Room {
  int side = 40;
  int floor = 0;
  int ceiling = 30;
  std::function<bool(int, int)> floor_seen = [](int, int) { return true; };
  std::function<bool(int, int)> ceiling_seen = [](int, int) { return true; };
  std::map<std::pair<int, int>, Column> extra;  // cells laid over the room's (furniture)
};

map_formats::MapCells roomMap(const Room& room) {
  map_formats::MapCells cells;
  cells.resolution = kRes;
  for (int x = 0; x < room.side; ++x) {
    for (int y = 0; y < room.side; ++y) {
      Column column;
      const bool wall = x == 0 || y == 0 || x == room.side - 1 || y == room.side - 1;
      if (wall) {
        for (int z = room.floor; z <= room.ceiling; ++z) column[z] = 1;
      } else {
        const bool floor = room.floor_seen(x, y), ceiling = room.ceiling_seen(x, y);
        if (floor || ceiling) {
          for (int z = room.floor + 1; z < room.ceiling; ++z) column[z] = -1;
        }
        if (floor) column[room.floor] = 1;
        if (ceiling) column[room.ceiling] = 1;
      }
      if (const auto it = room.extra.find({x, y}); it != room.extra.end()) {
        for (const auto& [z, c] : it->second) column[z] = c;
      }
      for (const auto& [z, c] : column) cells.cells.push_back({CellKey{x, y, z}, c > 0 ? 0.9 : 0.1, c, 0.1f});
    }
  }
  return cells;
}

// Columns holding an occupied cell whose centre lies in the band, and those of them that are walls.
struct BandColumns {
  std::size_t occupied = 0;
  std::size_t walls = 0;
};
BandColumns columnsInBand(const map_formats::MapCells& cells, const tools::WallBand& band, int side) {
  std::set<std::pair<int, int>> occupied;
  for (const auto& c : cells.cells) {
    const double centre = (c.key.z + 0.5) * cells.resolution;
    if (c.cell_class > 0 && centre >= band.z_min && centre <= band.z_max) occupied.insert({c.key.x, c.key.y});
  }
  BandColumns n{occupied.size(), 0};
  for (const auto& [x, y] : occupied)
    n.walls += (x == 0 || y == 0 || x == side - 1 || y == side - 1) ? 1U : 0U;
  return n;
}

// The walls' band of `cells`, expected to span [z_min, z_max] metres.
tools::WallBand expectBand(const map_formats::MapCells& cells, double z_min, double z_max) {
  const auto band = map_io::wallBand(cells);
  EXPECT_TRUE(band.has_value());
  if (!band) return {};
  EXPECT_NEAR(band->z_min, z_min, 1e-9) << band->reason;
  EXPECT_NEAR(band->z_max, z_max, 1e-9) << band->reason;
  return *band;
}

TEST(WallBand, ACeilingSeenMoreThanTheFloorIsNotTakenForTheFloor) {
  // A sensor near the ceiling: the ceiling is seen everywhere, the floor only in a ring by the walls.
  Room room;
  room.floor_seen = [&](int x, int y) { return std::min({x, y, room.side - 1 - x, room.side - 1 - y}) <= 3; };
  const auto cells = roomMap(room);
  // Right above the floor layer, 1.8 m high, under the ceiling at 3 m.
  const auto band = expectBand(cells, 0.1, 1.9);
  const auto n = columnsInBand(cells, band, room.side);
  EXPECT_EQ(n.walls, static_cast<std::size_t>(4 * (room.side - 1)));
  EXPECT_EQ(n.occupied, n.walls) << "only the walls are occupied in the band";
  // The floor and the ceiling are named by the height of their layer, as the navigation grid names its floor.
  EXPECT_NE(band.reason.find("floor at 0.00 m"), std::string::npos) << band.reason;
  EXPECT_NE(band.reason.find("ceiling at 3.00 m"), std::string::npos) << band.reason;
}

TEST(WallBand, AFloorSmearedOverTwoLayersIsLeftOutAndATableTopIsKept) {
  // Range noise puts the floor in layers 0 and 1; a table top 0.7 m up stands in the room, the floor under
  // it unseen.
  Room room;
  const auto table = [](int x, int y) { return x >= 10 && x < 16 && y >= 10 && y < 14; };
  room.floor_seen = [&](int x, int y) { return !table(x, y); };
  for (int x = 1; x < room.side - 1; ++x) {
    for (int y = 1; y < room.side - 1; ++y) {
      auto& column = room.extra[{x, y}];
      if (!table(x, y)) {
        column[1] = 1;
        continue;
      }
      column[7] = 1;
      for (int z = 1; z < 7; ++z) column[z] = 0;
    }
  }
  const auto cells = roomMap(room);
  const auto n = columnsInBand(cells, expectBand(cells, 0.2, 2.0), room.side);
  EXPECT_EQ(n.occupied - n.walls, 24U) << "the table's 6 x 4 columns";
}

TEST(WallBand, ARoomLowerThanABandIsShownWhole) {
  Room room;
  room.ceiling = 12;  // 1.2 m
  const auto cells = roomMap(room);
  const auto n = columnsInBand(cells, expectBand(cells, 0.1, 1.2), room.side);
  EXPECT_EQ(n.occupied, n.walls);
}

TEST(WallBand, TheBandFollowsTheMapsFrame) {
  // The same room 3.2 m below the map's origin (a sensor's own frame, the sensor high above the floor).
  Room room;
  room.floor = -32;
  room.ceiling = -2;
  room.ceiling_seen = [](int x, int) { return x < 5; };
  expectBand(roomMap(room), -3.1, -1.3);
}

TEST(WallBand, NothingOccupiedGivesNoBandAndAFloorAloneGivesTheBandAboveIt) {
  EXPECT_FALSE(map_io::wallBand(map_formats::MapCells{}).has_value());
  map_formats::MapCells floor;
  floor.resolution = kRes;
  for (int x = 0; x < 10; ++x) {
    floor.cells.push_back({CellKey{x, 0, 4}, 0.9, 1, 0.1f});
    floor.cells.push_back({CellKey{x, 0, 5}, 0.1, -1, 0.1f});
  }
  EXPECT_NE(expectBand(floor, 0.5, 2.3).reason.find("no walls"), std::string::npos);
}

TEST(WallBand, PngZminAndZmaxOverrideTheWallsBand) {
  const tools::WallBand walls{1, 18, 0.1, 1.9, "floor at 0.10 m"};
  const auto both = tools::pictureBand(walls, -0.5, 1.3, "the map");
  EXPECT_DOUBLE_EQ(both.z_min, -0.5);
  EXPECT_DOUBLE_EQ(both.z_max, 1.3);
  EXPECT_NE(both.why.find("--png-zmin and --png-zmax"), std::string::npos);
  const auto automatic = tools::pictureBand(walls, std::nullopt, std::nullopt, "the map");
  EXPECT_DOUBLE_EQ(automatic.z_min, 0.1);
  EXPECT_DOUBLE_EQ(automatic.z_max, 1.9);
  EXPECT_EQ(automatic.why, "the walls' band chosen from the map: floor at 0.10 m");
  // One bound alone keeps the other where that leaves a band, else keeps the band's height.
  const auto low = tools::pictureBand(walls, 0.5, std::nullopt, "the map");
  EXPECT_DOUBLE_EQ(low.z_max, 1.9);
  const auto high = tools::pictureBand(walls, 3.0, std::nullopt, "the map");
  EXPECT_NEAR(high.z_max, 4.8, 1e-9);
  const auto top = tools::pictureBand(walls, std::nullopt, 0.0, "the map");
  EXPECT_NEAR(top.z_min, -1.8, 1e-9);
  const auto none = tools::pictureBand(std::nullopt, std::nullopt, std::nullopt, "the map");
  EXPECT_LT(none.z_min, -1.0e6);
  EXPECT_GT(none.z_max, 1.0e6);
}

// The real capture (a VLP-16 standing still indoors, ../shared) mapped at 0.1 m as the README's headline
// command maps it (--static), with the sensor `height` metres above the body's origin (an extrinsic).
map_formats::MapCells realCaptureMap(const std::filesystem::path& pcap, const std::filesystem::path& calib,
                                double height) {
  pipeline::MapperConfig config;
  config.setResolution(0.1);
  config.fusion.extrinsic.translation_m = Eigen::Vector3d(0.2, 0.0, height);
  auto run = map_io::OfflineMapping::create(config);
  EXPECT_TRUE(run.ok()) << (run.ok() ? "" : run.error().message);
  map_io::PcapScanConfig pc;
  pc.calibration = calib;
  pc.min_range_m = config.fusion.measurement.min_range_m;
  const auto read = map_io::readPcapScans(pcap, pc, [&](const map_io::ScanRecord& scan) {
    run->addStaticScan(scan, Eigen::Isometry3d::Identity());
  });
  EXPECT_TRUE(read.ok()) << (read.ok() ? "" : read.error().message);
  return map_formats::collectCells(run->mapper().filter());
}

// Per class, the columns a top-down picture of the band shows in it (occupied wins, then free, then unknown).
struct PictureColumns {
  std::size_t occupied = 0;
  std::size_t free = 0;
  std::size_t unknown = 0;
};
PictureColumns pictureColumns(const map_formats::MapCells& cells, double z_min, double z_max) {
  std::map<std::pair<int, int>, std::int8_t> shown;
  for (const auto& c : cells.cells) {
    const double centre = (c.key.z + 0.5) * cells.resolution;
    if (centre < z_min || centre > z_max) continue;
    auto [it, fresh] = shown.try_emplace({c.key.x, c.key.y}, c.cell_class);
    if (!fresh && (c.cell_class > 0 || (c.cell_class < 0 && it->second == 0))) it->second = c.cell_class;
  }
  PictureColumns n;
  for (const auto& [xy, c] : shown) (c > 0 ? n.occupied : c < 0 ? n.free : n.unknown) += 1;
  return n;
}

class RealCaptureBand : public ::testing::TestWithParam<double> {};

// The capture's own layers (cells of 0.1 m, sensor frame) put the floor 1.6 to 1.8 m below the sensor and the
// ceiling 1.4 to 1.6 m above it: layers where horizontal surfaces outnumber standing cells. Its picture drawn
// with --png-zmin -0.5 --png-zmax 1.3 (set by hand to where the walls are) shows 2047 occupied and 13100 free
// columns; a band that shows the walls shows at least three quarters of the one and 60 % of the other.
TEST_P(RealCaptureBand, LiesBetweenTheFloorAndTheCeilingAndShowsTheWalls) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  OGF_REQUIRE_SHARED_FILE(calib, "data/real/calib/VLP-16.xml");
  const double height = GetParam();
  const auto cells = realCaptureMap(pcap, calib, height);
  const auto band = map_io::wallBand(cells);
  ASSERT_TRUE(band.has_value());
  EXPECT_GE(band->z_min, -1.6 + height) << band->reason;
  EXPECT_LE(band->z_max, 1.4 + height) << band->reason;
  EXPECT_NEAR(band->z_max - band->z_min, 1.8, 1e-9);
  const auto shown = pictureColumns(cells, band->z_min, band->z_max);
  EXPECT_GE(shown.occupied, 1535U) << "z " << band->z_min << " to " << band->z_max << ": " << band->reason;
  EXPECT_GE(shown.free, 7860U) << "z " << band->z_min << " to " << band->z_max << ": " << band->reason;
}

INSTANTIATE_TEST_SUITE_P(SensorHeights, RealCaptureBand, ::testing::Values(0.0, 0.8), [](const auto& test) {
  return test.param == 0.0 ? "SensorFrame" : "Extrinsic0p8m";
});

}  // namespace
