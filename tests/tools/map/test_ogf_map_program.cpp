// ogf-map as a program: on the real static capture it writes a map file and a CSV whose occupied cells lie
// on the decoded points; odometry that does not cover the scans is reported and exits non-zero; a bad
// odometry line is named; an LCM log with both pose types and a PCD with a VIEWPOINT map where they
// should; a simulated moving capture maps with CSV and LCM-log odometry; the .bt export reads back.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>
#include <octomap/OcTree.h>

#include <bot_core/pose_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "ogf/filter/map_file.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/pcd_file.hpp"
#include "run_program.hpp"
#include "scratch_dir.hpp"
#include "support/file_text.hpp"
#include "support/shared_data.hpp"
#include "synthetic_scan.hpp"

namespace {

using namespace ogf;
using ogf::testing::runProgram;

const std::string kMap = OGF_MAP_BINARY;
const std::string kSim = OGF_SIM_BINARY;
const std::string kMapper = OGF_MAPPER_BINARY;
const std::string kEval = OGF_EVAL_BINARY;
constexpr const char* kRealCalibration = "data/real/calib/VLP-16.xml";
constexpr const char* kRealCapture = "data/real/vlp-16-test-90deg-1-50-frames.pcap";

struct Row {
  double x, y, z, p, variance;
  int cls;
};

// The CSV's header line and its rows.
std::pair<std::string, std::vector<Row>> readCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r{};
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%d,%lf", &r.x, &r.y, &r.z, &r.p, &r.cls, &r.variance) == 6)
      rows.push_back(r);
  }
  return {header, rows};
}

// The numbers of the summary line, or -1s when there is none.
struct Summary {
  long long scans = -1, measurements = -1, cells = -1;
  std::string checksum;
};
Summary summaryOf(const std::string& stdout_text) {
  std::smatch m;
  static const std::regex re(R"(scans (\d+) measurements (\d+) cells (\d+) seconds [0-9.]+ checksum ([0-9a-f]+))");
  Summary s;
  if (std::regex_search(stdout_text, m, re)) {
    s.scans = std::stoll(m[1]);
    s.measurements = std::stoll(m[2]);
    s.cells = std::stoll(m[3]);
    s.checksum = m[4];
  }
  return s;
}

void writeFile(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

TEST(OgfMapProgram, StaticRealCaptureGivesAMapAndCsvWhoseOccupiedCellsLieOnTheDecodedPoints) {
  OGF_REQUIRE_SHARED_FILE(pcap, kRealCapture);
  ogf::testing::ScratchDir dir;
  const auto run = runProgram({kMap, "--pcap", pcap.string(), "--static", "--resolution", "0.2", "--max-range", "30",
                               "--out", (dir / "m.ogfmap").string(), "--export-csv", (dir / "m.csv").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const Summary s = summaryOf(run.stdout_text);
  EXPECT_GT(s.scans, 10) << run.stdout_text;
  EXPECT_GT(s.measurements, 0);
  auto loaded = filter::loadMapFile(dir / "m.ogfmap");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(static_cast<long long>(loaded->allocatedCells()), s.cells);

  const auto [header, rows] = readCsv(dir / "m.csv");
  EXPECT_EQ(header, "x,y,z,p,class,variance");
  EXPECT_EQ(static_cast<long long>(rows.size()), s.cells);

  // The cells the decoded returns (within the mapper's range) fall in.
  std::set<std::tuple<int, int, int>> hit;
  const auto cell = [](double v) { return static_cast<int>(std::floor(v / 0.2)); };
  map_io::PcapScanConfig pc;
  const auto decoded = map_io::readPcapScans(pcap, pc, [&](const map_io::ScanRecord& scan) {
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const Eigen::Vector3d p(scan.x[i], scan.y[i], scan.z[i]);
      const double r = p.norm();
      if (r >= 0.4 && r <= 30.0) hit.insert({cell(scan.x[i]), cell(scan.y[i]), cell(scan.z[i])});
    }
  });
  ASSERT_TRUE(decoded.ok());
  std::size_t occupied = 0, near = 0;
  for (const Row& r : rows) {
    if (r.cls != 1) continue;
    ++occupied;
    const int cx = cell(r.x), cy = cell(r.y), cz = cell(r.z);
    bool found = false;
    for (int dx = -1; dx <= 1 && !found; ++dx)
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dz = -1; dz <= 1 && !found; ++dz) found = hit.count({cx + dx, cy + dy, cz + dz}) > 0;
    near += found ? 1 : 0;
  }
  ASSERT_GT(occupied, 100u);
  EXPECT_GE(static_cast<double>(near), 0.98 * static_cast<double>(occupied)) << near << " of " << occupied;
}

TEST(OgfMapProgram, OdometryThatCoversNoScanIsReportedAndExitsNonZero) {
  OGF_REQUIRE_SHARED_FILE(pcap, kRealCapture);
  ogf::testing::ScratchDir dir;
  writeFile(dir / "odo.csv", "utime,x,y,z,qw,qx,qy,qz\n1000,0,0,0,1,0,0,0\n2000,0,0,0,1,0,0,0\n");
  const auto run = runProgram(
      {kMap, "--pcap", pcap.string(), "--odometry", (dir / "odo.csv").string(), "--out", (dir / "m").string()},
      dir.path());
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("not covered by the odometry"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("nothing could be mapped"), std::string::npos) << run.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "m"));
}

TEST(OgfMapProgram, MalformedOdometryLineIsNamedByFileAndLineAndTheRestIsUsed) {
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({kSim, "--out", (dir / "sim").string(), "--duration", "0.6"}, dir.path()).exit_code, 0);
  // Break line 3 of the simulator's odometry.
  std::ifstream in(dir / "sim" / "odometry.csv");
  std::ostringstream text;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) text << (n == 3 ? "12x,0,0" : line) << "\n";
  writeFile(dir / "odo.csv", text.str());
  const auto run = runProgram({kMap, "--pcap", (dir / "sim" / "capture.pcap").string(), "--odometry",
                               (dir / "odo.csv").string(), "--out", (dir / "m").string()},
                              dir.path());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find((dir / "odo.csv").string() + ":3:"), std::string::npos) << run.output;
  EXPECT_GT(summaryOf(run.stdout_text).scans, 0) << run.output;
}

TEST(OgfMapProgram, MovingSimCaptureMapsTheSameWithCsvAndLcmLogOdometry) {
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({kSim, "--out", (dir / "sim").string(), "--duration", "1.0"}, dir.path()).exit_code, 0);
  const auto pcap = (dir / "sim" / "capture.pcap").string();
  const auto csv = runProgram({kMap, "--pcap", pcap, "--odometry", (dir / "sim" / "odometry.csv").string(), "--out",
                               (dir / "a").string()},
                              dir.path());
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  const auto lcm = runProgram({kMap, "--pcap", pcap, "--odometry", (dir / "sim" / "odometry.lcmlog").string(),
                               "--out", (dir / "b").string()},
                              dir.path());
  ASSERT_EQ(lcm.exit_code, 0) << lcm.output;
  const Summary a = summaryOf(csv.stdout_text), b = summaryOf(lcm.stdout_text);
  EXPECT_GE(a.scans, 5) << csv.output;
  EXPECT_EQ(a.scans, b.scans);
  // The CSV holds positions to the micrometre, the log full doubles: the same cells, give or take a few.
  EXPECT_NEAR(static_cast<double>(a.measurements), static_cast<double>(b.measurements),
              0.01 * static_cast<double>(a.measurements));
  EXPECT_EQ(csv.output.find("not covered"), std::string::npos) << csv.output;
}

// --report-every: one row per interval of scan time, whose scans add up to the scans mapped and whose cells
// grow as the robot sees more.
TEST(OgfMapProgram, ReportEveryPrintsARowPerIntervalOfScanTime) {
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({kSim, "--out", (dir / "sim").string(), "--duration", "2.0"}, dir.path()).exit_code, 0);
  const auto run = runProgram({kMap, "--pcap", (dir / "sim" / "capture.pcap").string(), "--odometry",
                               (dir / "sim" / "odometry.csv").string(), "--report-every", "0.5", "--out",
                               (dir / "m").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::istringstream out(run.stdout_text);
  std::string line;
  std::getline(out, line);
  EXPECT_EQ(line.rfind("interval", 0), 0U) << run.stdout_text;
  int rows = 0;
  long long scans = 0;
  long long firstCells = 0, lastCells = 0;
  while (std::getline(out, line)) {
    int index = 0;
    long long n = 0, cells = 0;
    double mean = 0.0, max = 0.0, mapMb = 0.0, rssMb = 0.0;
    if (std::sscanf(line.c_str(), "%d %lld %lf %lf %lf %lf %lld", &index, &n, &mean, &max, &mapMb, &rssMb,
                    &cells) != 7) {
      break;  // the summary line
    }
    ++rows;
    EXPECT_EQ(index, rows);
    EXPECT_GT(mean, 0.0) << line;
    EXPECT_GE(max, mean) << line;
    EXPECT_GT(rssMb, mapMb) << line;
    EXPECT_GT(mapMb, 0.0) << line;
    scans += n;
    (rows == 1 ? firstCells : lastCells) = cells;
  }
  EXPECT_GE(rows, 4) << run.stdout_text;
  EXPECT_EQ(scans, summaryOf(run.stdout_text).scans) << run.stdout_text;
  EXPECT_GT(lastCells, firstCells) << run.stdout_text;
}

TEST(OgfMapProgram, PageDirGivesTheSameMapFileWithLessInMemoryAndLeavesNoPages) {
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({kSim, "--out", (dir / "sim").string(), "--world", "street", "--duration", "3.0"}, dir.path())
                .exit_code,
            0);
  const std::vector<std::string> input = {kMap, "--pcap", (dir / "sim" / "capture.pcap").string(), "--odometry",
                                          (dir / "sim" / "odometry.csv").string(), "--report-every", "1"};
  auto whole_args = input;
  whole_args.insert(whole_args.end(), {"--out", (dir / "whole.map").string()});
  auto paged_args = input;
  // The street capture reaches 30 m: regions 5 m beyond the sensor go out and come back scan by scan.
  paged_args.insert(paged_args.end(), {"--out", (dir / "paged.map").string(), "--page-dir",
                                       (dir / "pages").string(), "--page-out-distance", "5"});
  const auto whole = runProgram(whole_args, dir.path());
  const auto paged = runProgram(paged_args, dir.path());
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  ASSERT_EQ(paged.exit_code, 0) << paged.output;
  EXPECT_FALSE(summaryOf(whole.stdout_text).checksum.empty()) << whole.stdout_text;
  EXPECT_EQ(summaryOf(paged.stdout_text).checksum, summaryOf(whole.stdout_text).checksum);
  std::ifstream a(dir / "whole.map", std::ios::binary), b(dir / "paged.map", std::ios::binary);
  const std::string wa((std::istreambuf_iterator<char>(a)), {}), wb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_TRUE(!wa.empty() && wa == wb) << "the map files differ";
  EXPECT_NE(paged.output.find("paging: "), std::string::npos) << paged.output;
  EXPECT_TRUE(std::filesystem::is_empty(dir / "pages")) << "every page is read back before the map file is written";
  // The map in memory (column 5 of the last report row) is smaller with paging.
  const auto lastMapMb = [](const std::string& text) {
    std::istringstream out(text);
    std::string line;
    double last = 0.0;
    while (std::getline(out, line)) {
      int index = 0;
      long long n = 0;
      double mean = 0.0, max = 0.0, mapMb = 0.0;
      if (std::sscanf(line.c_str(), "%d %lld %lf %lf %lf", &index, &n, &mean, &max, &mapMb) == 5) last = mapMb;
    }
    return last;
  };
  EXPECT_LT(lastMapMb(paged.stdout_text), 0.8 * lastMapMb(whole.stdout_text)) << paged.stdout_text;
}

// A tiny LCM log: poses every 50 ms over 1 s (odometry_t, then bot_core.pose_t), two wall scans inside
// that span and one after it.
void writeTinyLog(const std::filesystem::path& path, std::int64_t t0) {
  lcm::LogFile log(path.string(), "w");
  ASSERT_TRUE(log.good());
  std::int64_t eventnum = 0;
  const auto write = [&](const std::string& channel, const auto& msg, std::int64_t utime) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    ASSERT_GE(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
    lcm::LogEvent e{eventnum++, utime, channel, static_cast<std::int32_t>(bytes.size()), bytes.data()};
    ASSERT_EQ(log.writeEvent(&e), 0);
  };
  const auto scanAt = [&](std::int64_t t) {
    const auto s = ogf::testing::wallScan(4.1, t);
    ogf::lidar_scan_t m{};
    m.utime = t;
    m.device_utime_start = t;
    m.host_utime_start = t;
    m.num_points = static_cast<std::int32_t>(s.size());
    m.x = s.x;
    m.y = s.y;
    m.z = s.z;
    m.intensity.assign(s.size(), 0);
    m.ring.assign(s.size(), 0);
    m.laser_id.assign(s.size(), 0);
    m.azimuth_deg.assign(s.size(), 0.0f);
    m.time_offset_ns = s.time_offset_ns;
    m.return_type.assign(s.size(), 1);
    write("VELODYNE_SCAN", m, t);
  };
  for (int i = 0; i <= 20; ++i) {
    const std::int64_t t = t0 + i * 50'000;
    if (i < 10) {
      ogf::odometry_t o{};
      o.utime = t;
      o.orientation[0] = 1.0;
      write("POSE", o, t);
    } else {
      bot_core::pose_t p{};
      p.utime = t;
      p.orientation[0] = 1.0;
      write("POSE", p, t);
    }
    if (i == 4 || i == 14) scanAt(t);
  }
  scanAt(t0 + 5'000'000);
}

TEST(OgfMapProgram, LcmLogWithBothPoseTypesMapsTheCoveredScansAndCountsTheOther) {
  ogf::testing::ScratchDir dir;
  writeTinyLog(dir / "tiny.lcmlog", 1'700'000'000'000'000);
  const auto run = runProgram({kMap, "--lcm-log", (dir / "tiny.lcmlog").string(), "--out", (dir / "m").string(),
                               "--export-csv", (dir / "m.csv").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(summaryOf(run.stdout_text).scans, 2) << run.output;
  EXPECT_NE(run.output.find("1 of 3 scans not covered"), std::string::npos) << run.output;
  const auto [header, rows] = readCsv(dir / "m.csv");
  std::size_t occupied = 0;
  for (const Row& r : rows)
    if (r.cls == 1) {
      ++occupied;
      EXPECT_NEAR(r.x, 4.1, 1e-3);
    }
  EXPECT_GT(occupied, 0u);
}

TEST(OgfMapProgram, PcdRaysStartAtTheViewpointAndTheBtExportReadsBack) {
  ogf::testing::ScratchDir dir;
  // A wall at x = 5.1 seen from the viewpoint (1, 2, 0.5), points in the same frame as the viewpoint.
  std::ostringstream pts;
  int n = 0;
  for (int iy = -20; iy <= 20; ++iy)
    for (int iz = -10; iz <= 10; ++iz, ++n) pts << "5.1 " << 2.0 + 0.05 * iy << " " << 0.5 + 0.05 * iz << "\n";
  writeFile(dir / "wall.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
                                  std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 1 2 0.5 1 0 0 0\nPOINTS " +
                                  std::to_string(n) + "\nDATA ascii\n" + pts.str());
  const auto run = runProgram({kMap, "--pcd", (dir / "wall.pcd").string(), (dir / "wall.pcd").string(), "--out",
                               (dir / "m").string(), "--export-csv", (dir / "m.csv").string(), "--export-bt",
                               (dir / "m.bt").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(summaryOf(run.stdout_text).scans, 2);
  const auto [header, rows] = readCsv(dir / "m.csv");
  bool free_in_front = false;
  std::size_t occupied = 0;
  for (const Row& r : rows) {
    if (r.cls == 1) {
      ++occupied;
      EXPECT_NEAR(r.x, 5.1, 1e-3);
    }
    // Air between the viewpoint and the wall, on the central ray (cell centre (3.1, 2.1, 0.5)).
    if (std::abs(r.x - 3.1) < 1e-3 && std::abs(r.y - 2.1) < 1e-3 && std::abs(r.z - 0.5) < 1e-3)
      free_in_front = r.cls == -1;
  }
  EXPECT_GT(occupied, 20u);
  EXPECT_TRUE(free_in_front);
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary((dir / "m.bt").string()));
  const octomap::OcTreeNode* wall = tree.search(5.1, 2.1, 0.5);
  ASSERT_NE(wall, nullptr);
  EXPECT_TRUE(tree.isNodeOccupied(wall));
}

// The robot's own ogf-mapper configuration (nested `map:` section, daemon-only keys) is read as the daemon
// reads it: its resolution and filter settings make the map; a typo in it is still an error naming the key.
TEST(OgfMapProgram, TheMapperDaemonsConfigurationFileIsAccepted) {
  ogf::testing::ScratchDir dir;
  std::ostringstream pts;
  int n = 0;
  for (int iy = -10; iy <= 10; ++iy, ++n) pts << "5.1 " << 0.05 * iy << " 0.5\n";
  writeFile(dir / "wall.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
                                  std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0.5 1 0 0 0\nPOINTS " +
                                  std::to_string(n) + "\nDATA ascii\n" + pts.str());
  writeFile(dir / "mapper.yaml",
            "lcm_url: \"\"\nstate_dir: /var/lib/ogf\nmap:\n  resolution: 0.5\n  max_range: 20\n"
            "filter:\n  threads: 1\n  free_clamp_z: 2.5\nfusion:\n  max_pending_scans: 10\n");
  const auto run = runProgram({kMap, "--config", (dir / "mapper.yaml").string(), "--pcd",
                               (dir / "wall.pcd").string(), "--out", (dir / "m").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("ogf-map does not use lcm_url, state_dir, fusion.max_pending_scans (ogf-mapper's): ignored"),
            std::string::npos)
      << run.output;
  const auto map = ogf::filter::loadMapFile(dir / "m");
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->config().resolution, 0.5);
  EXPECT_EQ(map->config().freeClampZ, 2.5);

  writeFile(dir / "typo.yaml", "map:\n  resolutoin: 0.5\n");
  const auto bad = runProgram({kMap, "--config", (dir / "typo.yaml").string(), "--pcd",
                               (dir / "wall.pcd").string(), "--out", (dir / "m2").string()},
                              dir.path());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("resolutoin"), std::string::npos) << bad.output;
}

TEST(OgfMapProgram, AMapMadeBeforeIsExportedWithoutMapping) {
  ogf::testing::ScratchDir dir;
  std::ostringstream pts;
  int n = 0;
  for (int iy = -20; iy <= 20; ++iy)
    for (int iz = -10; iz <= 10; ++iz, ++n) pts << "5.1 " << 0.05 * iy << " " << 0.05 * iz << "\n";
  writeFile(dir / "wall.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
                                  std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
                                  std::to_string(n) + "\nDATA ascii\n" + pts.str());
  ASSERT_EQ(runProgram({kMap, "--pcd", (dir / "wall.pcd").string(), "--out", (dir / "m").string(), "--export-csv",
                        (dir / "m.csv").string()},
                       dir.path())
                .exit_code,
            0);
  const auto run = runProgram({kMap, "--from-map", (dir / "m").string(), "--export-csv", (dir / "again.csv").string(),
                               "--export-pcd", (dir / "m.pcd").string(), "--png", (dir / "png").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.stdout_text.find("map file cells "), std::string::npos) << run.stdout_text;
  EXPECT_EQ(ogf::testing::fileText(dir / "again.csv"), ogf::testing::fileText(dir / "m.csv"));
  const auto cloud = ogf::map_io::readPcdFile(dir / "m.pcd");
  ASSERT_TRUE(cloud.ok()) << cloud.error().message;
  const auto [header, rows] = readCsv(dir / "m.csv");
  std::size_t occupied = 0;
  for (const Row& r : rows) occupied += r.cls == 1 ? 1U : 0U;
  EXPECT_GT(occupied, 20u);
  EXPECT_EQ(cloud->points.size(), occupied);
  for (const auto& p : cloud->points) EXPECT_NEAR(p.x(), 5.1, 1e-3);
  EXPECT_TRUE(std::filesystem::exists(dir / "png" / "occupancy.png"));
  // A file that is no map is named, exit 1.
  writeFile(dir / "junk", "not a map");
  const auto junk = runProgram({kMap, "--from-map", (dir / "junk").string(), "--export-pcd", (dir / "j.pcd").string()},
                               dir.path());
  EXPECT_EQ(junk.exit_code, 1) << junk.output;
  EXPECT_NE(junk.output.find("junk"), std::string::npos) << junk.output;
}

TEST(OgfMapProgram, NoInputIsAUsageError) {
  ogf::testing::ScratchDir dir;
  const auto run = runProgram({kMap, "--out", (dir / "m").string()}, dir.path());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("no input"), std::string::npos) << run.output;
}

}  // namespace

namespace {
// utime -> (x, y) of a pose CSV (utime,x,y,z,qw,qx,qy,qz with a header line).
std::map<long long, std::pair<double, double>> readPositions(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::map<long long, std::pair<double, double>> out;
  long long t = 0;
  double x = 0, y = 0;
  while (std::getline(in, line))
    if (std::sscanf(line.c_str(), "%lld,%lf,%lf", &t, &x, &y) == 3) out[t] = {x, y};
  return out;
}

// Mean planar distance of `poses` from the true pose at (or just after) the same time.
double meanPositionError(const std::map<long long, std::pair<double, double>>& poses,
                         const std::map<long long, std::pair<double, double>>& truth) {
  double sum = 0.0;
  for (const auto& [t, p] : poses) {
    auto it = truth.lower_bound(t);
    if (it == truth.end()) --it;
    sum += std::hypot(p.first - it->second.first, p.second - it->second.second);
  }
  return poses.empty() ? 1e9 : sum / static_cast<double>(poses.size());
}
}  // namespace

TEST(OgfMapProgram, ScanMatchingCorrectsDriftingOdometryAndWritesTheCorrectedTrajectory) {
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({kSim, "--out", (dir / "sim").string(), "--duration", "8", "--odometry-drift", "slip-and-bias",
                        "--seed", "3"},
                       dir.path())
                .exit_code,
            0);
  // The simulated sensor sits 1 m above the body (sim.yaml's sensor_to_body).
  writeFile(dir / "map.yaml", "map:\n  extrinsic: {translation: [0, 0, 1], quaternion: [1, 0, 0, 0]}\n");
  const auto corrected = dir / "corrected.csv";
  const auto run = runProgram({kMap, "--config", (dir / "map.yaml").string(), "--pcap",
                               (dir / "sim" / "capture.pcap").string(), "--odometry",
                               (dir / "sim" / "odometry.csv").string(), "--out", (dir / "m").string(),
                               "--pose-correction", "scan-match", "--corrected-out", corrected.string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto poses = readPositions(corrected);
  EXPECT_EQ(static_cast<long long>(poses.size()), summaryOf(run.stdout_text).scans);
  const auto truth = readPositions(dir / "sim" / "trajectory_true.csv");
  const double odometry_error = meanPositionError(readPositions(dir / "sim" / "odometry.csv"), truth);
  const double corrected_error = meanPositionError(poses, truth);
  EXPECT_GT(odometry_error, 0.05);  // the drift is there to correct
  EXPECT_LT(corrected_error, 0.5 * odometry_error) << "odometry " << odometry_error << " m";
}

TEST(OgfMapProgram, PoseCorrectionFlagsAreCheckedBeforeAnyWork) {
  ogf::testing::ScratchDir dir;
  const auto bogus = runProgram({kMap, "--pcap", "x.pcap", "--odometry", "o.csv", "--out", "m", "--pose-correction",
                                 "gmapping"},
                                dir.path());
  EXPECT_EQ(bogus.exit_code, 2) << bogus.output;
  EXPECT_NE(bogus.output.find("none, scan-match, rbpf"), std::string::npos) << bogus.output;
  const auto orphan = runProgram({kMap, "--pcap", "x.pcap", "--odometry", "o.csv", "--out", "m", "--corrected-out",
                                  "c.csv"},
                                 dir.path());
  EXPECT_EQ(orphan.exit_code, 2) << orphan.output;
  const auto tripod = runProgram({kMap, "--pcap", "x.pcap", "--static", "--out", "m", "--pose-correction", "rbpf"},
                                 dir.path());
  EXPECT_EQ(tripod.exit_code, 2) << tripod.output;
}

namespace {

// The capture's scans and the span of their host (receive) times.
struct HostSpan {
  long long scans = 0;
  std::int64_t first = 0, last = 0;
};
HostSpan hostSpanOf(const std::filesystem::path& pcap) {
  HostSpan span;
  map_io::PcapScanConfig pc;
  const auto read = map_io::readPcapScans(pcap, pc, [&](const map_io::ScanRecord& scan) {
    if (span.scans++ == 0) span.first = scan.host_utime_start;
    span.last = std::max(span.last, scan.host_utime_start);
  });
  EXPECT_TRUE(read.ok());
  return span;
}

// A robot standing still, its odometry stamped on the host clock at 100 Hz a second either side of the
// capture, as a driver computer's odometry would be for a sensor without GPS.
void writeHostOdometry(const HostSpan& span, const std::filesystem::path& path) {
  std::ostringstream csv;
  csv << "utime,x,y,z,qw,qx,qy,qz\n";
  for (std::int64_t t = span.first - 1'000'000; t <= span.last + 1'000'000; t += 10'000) csv << t << ",0,0,0,1,0,0,0\n";
  writeFile(path, csv.str());
}

// The YAML block the README gives as my-mapper.yaml.
std::string readmeMapperYaml() {
  std::ifstream in(OGF_README_PATH);
  std::stringstream text;
  text << in.rdbuf();
  const std::string readme = text.str();
  const auto named = readme.find("with `my-mapper.yaml`");
  if (named == std::string::npos) return {};
  const auto block = readme.find("```yaml\n", named);
  if (block == std::string::npos) return {};
  const auto from = block + 8;
  return readme.substr(from, readme.find("```", from) - from);
}

}  // namespace

// The README's robot configuration (time_base: auto and an extrinsic) maps a capture without GPS whose
// odometry is on the host clock: auto times each scan on the host clock, as ogf-mapper does.
TEST(OgfMapProgram, TheReadmesMapperYamlMapsEveryScanOfTheRealCaptureWithHostClockOdometry) {
  OGF_REQUIRE_SHARED_FILE(pcap, kRealCapture);
  OGF_REQUIRE_SHARED_FILE(calib, kRealCalibration);
  ogf::testing::ScratchDir dir;
  const std::string yaml = readmeMapperYaml();
  ASSERT_NE(yaml.find("time_base: auto"), std::string::npos) << yaml;
  writeFile(dir / "my-mapper.yaml", yaml);
  const HostSpan span = hostSpanOf(pcap);
  ASSERT_GT(span.scans, 40);
  writeHostOdometry(span, dir / "host.csv");
  const auto run = runProgram({kMap, "--pcap", pcap.string(), "--calib", calib.string(), "--odometry",
                               (dir / "host.csv").string(), "--config", (dir / "my-mapper.yaml").string(), "--out",
                               (dir / "m").string()},
                              dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(summaryOf(run.stdout_text).scans, span.scans) << run.output;
  EXPECT_EQ(run.output.find("not covered"), std::string::npos) << run.output;
}

// Scans timed on the device clock against host-clock odometry: none is covered, and the log says once that
// the two are on different clocks, with both times, the offset and the flag and key that fix it.
TEST(OgfMapProgram, OdometryOnAnotherClockIsNamedWithBothTimesTheOffsetAndTheFix) {
  OGF_REQUIRE_SHARED_FILE(pcap, kRealCapture);
  ogf::testing::ScratchDir dir;
  const HostSpan span = hostSpanOf(pcap);
  writeHostOdometry(span, dir / "host.csv");
  const auto run = runProgram({kMap, "--pcap", pcap.string(), "--odometry", (dir / "host.csv").string(), "--time",
                               "device", "--out", (dir / "m").string()},
                              dir.path());
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("nothing could be mapped"), std::string::npos) << run.output;
  const auto at = run.output.find("different clocks");
  ASSERT_NE(at, std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("different clocks", at + 1), run.output.find("different clocks: see the clocks line"))
      << run.output;
  const std::string line = run.output.substr(at, run.output.find('\n', at) - at);
  EXPECT_NE(line.find("on the device clock"), std::string::npos) << line;
  EXPECT_NE(line.find("on the host clock"), std::string::npos) << line;
  EXPECT_NE(line.find("offset "), std::string::npos) << line;
  EXPECT_NE(line.find("time_base: host (--time host)"), std::string::npos) << line;
  static const std::regex iso(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z)");
  EXPECT_EQ(std::distance(std::sregex_iterator(line.begin(), line.end(), iso), std::sregex_iterator()), 3) << line;
}

// One file for every program: ogf-mapper reads it (and prints it back), ogf-map and ogf-eval map with it,
// ignoring the daemon's keys; its pose_source: static is their --static.
TEST(OgfMapProgram, OneConfigurationFileIsAcceptedByOgfMapperOgfMapAndOgfEval) {
  OGF_REQUIRE_SHARED_FILE(pcap, kRealCapture);
  ogf::testing::ScratchDir dir;
  writeFile(dir / "robot.yaml",
            "lcm_url: \"\"\nchannels: {scan: VELODYNE_SCAN, pose: POSE}\nstate_dir: \"\"\ntime_base: auto\n"
            "pose_source: static\nsnapshot_interval_s: 20\nmap:\n  resolution: 0.2\n  max_range: 30\n"
            "filter:\n  sigma: auto\n  threads: 1\nfusion:\n  max_pending_scans: 10\n");
  const auto mapper = runProgram({kMapper, "--config", (dir / "robot.yaml").string(), "--print-config"}, dir.path());
  ASSERT_EQ(mapper.exit_code, 0) << mapper.output;
  EXPECT_NE(mapper.stdout_text.find("\npose_source: static"), std::string::npos) << mapper.stdout_text;

  const auto from_file = runProgram({kMap, "--config", (dir / "robot.yaml").string(), "--pcap", pcap.string(), "--out",
                                     (dir / "a").string()},
                                    dir.path());
  ASSERT_EQ(from_file.exit_code, 0) << from_file.output;
  EXPECT_NE(from_file.output.find("ogf-map does not use lcm_url, channels.scan, channels.pose, state_dir"),
            std::string::npos)
      << from_file.output;
  const auto flags = runProgram({kMap, "--static", "--pcap", pcap.string(), "--resolution", "0.2", "--out",
                                 (dir / "b").string()},
                                dir.path());
  ASSERT_EQ(flags.exit_code, 0) << flags.output;
  EXPECT_EQ(summaryOf(from_file.stdout_text).checksum, summaryOf(flags.stdout_text).checksum);
  EXPECT_FALSE(summaryOf(flags.stdout_text).checksum.empty()) << flags.stdout_text;

  const auto eval = runProgram({kEval, "--config", (dir / "robot.yaml").string(), "--pcap", pcap.string(),
                                "--no-octomap"},
                               dir.path());
  EXPECT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_NE(eval.output.find("ogf-eval does not use"), std::string::npos) << eval.output;
}
