// The walls' band of the pictures on the simulated worlds: each world's capture (a short drive of its default
// trajectory) mapped at 0.2 m through the library, and its ground truth, get a band above the ground and
// under the lowest roof of the world, whose occupied columns are the truth's walls and obstacles, not open
// ground.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <utility>

#include "ogf/eval/sim_measurements.hpp"
#include "ogf/eval/topdown_figures.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/topdown_png.hpp"
#include "ogf/sim/scene.hpp"
#include "ogf/sim/simulation.hpp"

namespace {

namespace fs = std::filesystem;
using namespace ogf;

struct WorldCase {
  const char* name;
  double
      roof_m;  // the lowest top of the world's walls (tools/lib/sim/presets/<name>.yaml): the band stays under it
};

// lab: walls and ceiling at 3 m; warehouse: roof at 8 m; street and avenue: the lowest facade is 8 m high.
const WorldCase kWorlds[] = {{"lab", 3.0}, {"warehouse", 8.0}, {"street", 8.0}, {"avenue", 8.0}};

class WallBandWorld : public ::testing::TestWithParam<WorldCase> {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ogf-wall-band-" + std::string(GetParam().name) + "-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// The columns whose cells with centres in the band hold an occupied cell of the map.
using Columns = std::set<std::pair<int, int>>;

Columns occupiedColumns(const map_formats::MapCells& cells, const tools::WallBand& band) {
  Columns out;
  for (const auto& c : cells.cells) {
    const double centre = (c.key.z + 0.5) * cells.resolution;
    if (c.cell_class > 0 && centre >= band.z_min && centre <= band.z_max) out.insert({c.key.x, c.key.y});
  }
  return out;
}

// The truth's solid columns in the band: an occupied cell (a surface) or an unobservable one (a solid's
// inside, where a map's occupancy spreads a cell or two behind the surface).
Columns solidColumns(const sim::GroundTruth& truth, const tools::WallBand& band) {
  Columns out;
  for (std::size_t i = 0; i < truth.cells.size(); ++i) {
    if (truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Free)) continue;
    const CellKey k = truth.keyOf(i);
    const double centre = (k.z + 0.5) * truth.resolution;
    if (centre >= band.z_min && centre <= band.z_max) out.insert({k.x, k.y});
  }
  return out;
}

TEST_P(WallBandWorld, MapAndTruthBandsLieBetweenGroundAndRoofAndShowTheTruthsWalls) {
  const WorldCase world = GetParam();
  auto scene = sim::presetScene(world.name);
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto trajectory = sim::resolveTrajectory(*scene, "");
  ASSERT_TRUE(trajectory.ok()) << trajectory.error().message;
  sim::SimulationConfig sim_config;
  sim_config.duration_s = 1.5;
  auto report = sim::runSimulation(*scene, *trajectory, sim_config, dir_.string());
  ASSERT_TRUE(report.ok()) << report.error().message;

  pipeline::MapperConfig config;
  config.setResolution(0.2);
  auto extrinsic = eval::readSimExtrinsic(dir_);
  ASSERT_TRUE(extrinsic.ok()) << extrinsic.error().message;
  config.fusion.extrinsic = *extrinsic;
  auto run = map_io::OfflineMapping::create(config);
  ASSERT_TRUE(run.ok()) << run.error().message;
  auto odometry = map_io::readOdometry(dir_ / "odometry.csv");
  ASSERT_TRUE(odometry.ok()) << odometry.error().message;
  run->setOdometry(odometry->poses);
  map_io::PcapScanConfig pc;
  pc.min_range_m = config.fusion.measurement.min_range_m;
  auto read = map_io::readPcapScans(dir_ / "capture.pcap", pc, [&](const map_io::ScanRecord& scan) {
    run->addScan(scan, map_io::TimeBase::kDevice);
  });
  ASSERT_TRUE(read.ok()) << read.error().message;
  ASSERT_GT(run->counts().scans_mapped, 10);
  const auto cells = map_formats::collectCells(run->mapper().filter());

  const auto truth_band = eval::wallBand(report->truth);
  ASSERT_TRUE(truth_band.has_value());
  const auto map_band = map_io::wallBand(cells);
  ASSERT_TRUE(map_band.has_value());
  for (const auto* band : {&*truth_band, &*map_band}) {
    SCOPED_TRACE(std::string(band == &*map_band ? "map" : "truth") + " band z " +
                 std::to_string(band->z_min) + " to " + std::to_string(band->z_max) + ": " + band->reason);
    EXPECT_GE(band->z_min, 0.0) << "the ground's cells lie below z = 0";
    EXPECT_LE(band->z_max, world.roof_m);
    EXPECT_NEAR(band->z_max - band->z_min, 1.8, 1e-9);
  }
  // The map's occupied columns in its band are the truth's walls and obstacles there (within a cell: the map
  // blurs them), not open ground, and there are many of them: the picture shows walls, not the ground or
  // nothing.
  const Columns map_walls = occupiedColumns(cells, *map_band);
  const Columns truth_walls = solidColumns(report->truth, *map_band);
  std::size_t on_truth = 0;
  for (const auto& [x, y] : map_walls) {
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx)
      for (int dy = -1; dy <= 1 && !near; ++dy) near = truth_walls.count({x + dx, y + dy}) > 0;
    on_truth += near ? 1U : 0U;
  }
  EXPECT_GE(map_walls.size(), 100U) << map_band->reason;
  EXPECT_GE(static_cast<double>(on_truth), 0.9 * static_cast<double>(map_walls.size())) << map_band->reason;
}

INSTANTIATE_TEST_SUITE_P(Worlds, WallBandWorld, ::testing::ValuesIn(kWorlds),
                         [](const auto& test) { return std::string(test.param.name); });

}  // namespace
