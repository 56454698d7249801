// ogf-mapper's inputs, as a real process on real LCM (udpm on loopback), the test publishing the scans and
// the odometry itself:
// - pose_source static (--static): every scan is mapped at static_pose without odometry, and what arrives
//   on POSE is counted and said once;
// - scans without odometry: one warning naming the pose channel, the status says WAITING_FOR_POSES, and
//   every scan dropped counts as dropped for want of a pose, none as the mapper falling behind; odometry
//   coming back is said once; poses without scans are said once too;
// - a pause of the sensor stream longer than fusion.max_time_ahead_s, then a stale partial scan dated
//   before the pause, then the scans on the resumed clock: none is refused;
// - a burst of costly scans into a small queue: the drops count as the mapper falling behind (also with a
//   static pose) and one warning says so with the count and what helps; a scan too large for the queue
//   is named;
// - the map id the log says at a restart is the one map queries answer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <ogf/mapper_status_t.hpp>
#include <regex>
#include <string>
#include <thread>

#include "scan_feeder.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Status = ogf::mapper_status_t;
using Mapper = ogf::testing::DaemonProcess<Status>;

const std::string kBin = OGF_BIN_DIR;

std::int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::size_t occurrences(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + needle.size())) ++n;
  return n;
}

// The feeder's first scan (the body at (1.5, 0, 0.5), facing +x, in a 10 m x 8 m room), dated `utime` on both
// clocks: what a sensor that does not move sends, scan after scan.
ogf::lidar_scan_t fixedSensorScan(std::int64_t seq, std::int64_t utime, int points = 1500) {
  ogf::lidar_scan_t s = ogf::testing::feedStep(0, points).scan;
  const std::int64_t span = s.device_utime_end - s.device_utime_start;
  s.seq = seq;
  s.utime = s.device_utime_start = s.host_utime_start = utime;
  s.device_utime_end = s.host_utime_end = utime + span;
  return s;
}

class MapperInputsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast())
      GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-mapper-inputs");
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  // ogf-mapper with `config` (YAML) and `flags`, logging at info.
  std::unique_ptr<Mapper> startMapper(const std::string& url, const std::string& config,
                                      std::vector<std::string> flags, const std::string& log = "mapper.log") {
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\n" << config;
    std::vector<std::string> args{
        kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "mapper.yaml").string(),
        "--log-level",        "info"};
    args.insert(args.end(), flags.begin(), flags.end());
    return std::make_unique<Mapper>(args, (dir_ / log).string(), url, ogf::testing::kMapperStatusChannel);
  }
  // ogf-map-query with `args`: its exit status and output.
  std::pair<int, std::string> query(const std::string& url, std::vector<std::string> args) {
    args.insert(args.begin(), {kBin + "/ogf-map-query", "--lcm-url", url});
    ChildProcess q(args, (dir_ / ("query" + std::to_string(++queries_) + ".log")).string());
    const auto rc = q.wait(20s);
    return {rc.value_or(-1), q.log()};
  }

  fs::path dir_;
  int queries_ = 0;
};

TEST_F(MapperInputsTest, StaticPoseMapsEveryScanWithoutOdometryAtTheConfiguredPoseAndIgnoresPoses) {
  const std::string url = ogf::testing::loopbackUdpmUrl(81);
  // The scans see the room from (1.5, 0, 0.5): the wall at x = 5 is 3.5 m ahead of the sensor.
  auto mapper = startMapper(url, "static_pose: {translation: [1.5, 0, 0.5]}\n", {"--static", "--in-memory"});
  ASSERT_TRUE(mapper->reportsStatus(10s));
  EXPECT_NE(mapper->log().find("mapping VELODYNE_SCAN with a static pose on "), std::string::npos)
      << mapper->log();

  lcm::LCM lcm(url);
  constexpr int kScans = 30;
  const std::int64_t t0 = wallUtime();
  for (int i = 0; i < kScans; ++i) {
    const auto scan = fixedSensorScan(i, t0 + i * 100'000);
    lcm.publish("VELODYNE_SCAN", &scan);
    if (i == 10)
      for (const auto& p : ogf::testing::feedStep(0).poses) lcm.publish("POSE", &p);
    std::this_thread::sleep_for(20ms);
    for (int w = 0; w < 400; ++w) {  // at most 2 scans waiting for the mapper
      const auto s = mapper->latestStatus();
      if (!s || s->scans_in - s->scans_mapped - s->scans_dropped_behind < 2) break;
      std::this_thread::sleep_for(5ms);
    }
  }
  const auto done = mapper->waitForStatus([](const Status& s) { return s.scans_mapped == kScans; }, 30s);
  ASSERT_TRUE(done) << mapper->log();
  EXPECT_EQ(done->pose_source, Status::POSE_SOURCE_STATIC);
  EXPECT_EQ(done->scans_dropped_no_pose + done->scans_dropped_behind + done->scans_refused_time, 0);
  EXPECT_EQ(done->poses_ignored, static_cast<std::int64_t>(ogf::testing::feedStep(0).poses.size()));
  EXPECT_EQ(done->poses_in, 0) << "an ignored pose is not an odometry input";
  EXPECT_EQ(done->inputs, Status::INPUTS_OK);

  // The wall lies where static_pose puts it, not where the body at the origin would.
  auto [rc, out] = query(url, {"cell", "5.05", "0.1", "1.0", "3.55", "0.1", "1.0"});
  ASSERT_EQ(rc, 0) << out;
  EXPECT_TRUE(std::regex_search(out, std::regex("5\\.050 +0\\.100 +1\\.000 +\\S+ +occ"))) << out;
  EXPECT_FALSE(std::regex_search(out, std::regex("3\\.550 +0\\.100 +1\\.000 +\\S+ +occ"))) << out;

  EXPECT_TRUE(mapper->stop());
  EXPECT_EQ(occurrences(mapper->log(), "but the pose is static"), 1U) << mapper->log();
}

TEST_F(MapperInputsTest,
       ScansWithoutOdometryAreSaidOnceNamingThePoseChannelAndDroppedForWantOfAPoseNotBehind) {
  const std::string url = ogf::testing::loopbackUdpmUrl(82);
  auto mapper = startMapper(url, "", {"--in-memory"});
  ASSERT_TRUE(mapper->reportsStatus(10s));
  lcm::LCM lcm(url);
  int i = 0;
  // A burst, as a log played fast (more scans than the queue holds), then 10 Hz for 5 s; no odometry.
  const auto scanOnly = [&](int k) {
    const auto step = ogf::testing::feedStep(k, 400);
    lcm.publish("VELODYNE_SCAN", &step.scan);
  };
  for (; i < 30; ++i) {
    scanOnly(i);
    std::this_thread::sleep_for(2ms);
  }
  for (; i < 80; ++i) {
    scanOnly(i);
    std::this_thread::sleep_for(100ms);
  }
  const auto waiting = mapper->waitForStatus(
      [&](const Status& s) {
        return s.scans_in == i && s.scans_dropped_no_pose + s.scans_dropped_behind == i;
      },
      10s);
  ASSERT_TRUE(waiting) << mapper->log();
  EXPECT_EQ(waiting->scans_dropped_behind, 0) << "no scan could be mapped: the queue is not to blame";
  EXPECT_EQ(waiting->scans_dropped_no_pose, i);
  EXPECT_EQ(waiting->inputs, Status::INPUTS_WAITING_FOR_POSES);
  EXPECT_EQ(waiting->last_pose_age_s, -1.0f);
  EXPECT_GE(waiting->last_scan_age_s, 0.0f);
  EXPECT_EQ(waiting->pose_source, Status::POSE_SOURCE_ODOMETRY);
  std::string log = mapper->log();
  EXPECT_EQ(occurrences(log, "scans arrive on VELODYNE_SCAN but no pose on POSE"), 1U) << log;
  EXPECT_NE(log.find("--static"), std::string::npos)
      << "the warning names the fix for a fixed sensor: " << log;

  // The odometry comes: said once, and the scans are mapped.
  const int first_covered = i + 1;  // the first scan of a resumed odometry begins before its first pose
  for (; i < 100; ++i) {
    const auto step = ogf::testing::feedStep(i, 400);
    for (const auto& p : step.poses) lcm.publish("POSE", &p);
    lcm.publish("VELODYNE_SCAN", &step.scan);
    std::this_thread::sleep_for(100ms);
  }
  const auto ok = mapper->waitForStatus(
      [&](const Status& s) {
        return s.inputs == Status::INPUTS_OK && s.scans_mapped >= i - first_covered - 1;
      },
      10s);
  ASSERT_TRUE(ok) << mapper->log();
  EXPECT_EQ(ok->scans_dropped_behind, 0);
  log = mapper->log();
  EXPECT_EQ(occurrences(log, "poses arrive on POSE again"), 1U) << log;

  // Odometry without scans.
  for (; i < 140; ++i) {
    for (const auto& p : ogf::testing::feedStep(i, 400).poses) lcm.publish("POSE", &p);
    std::this_thread::sleep_for(100ms);
  }
  const auto no_scans =
      mapper->waitForStatus([](const Status& s) { return s.inputs == Status::INPUTS_WAITING_FOR_SCANS; }, 10s);
  ASSERT_TRUE(no_scans) << mapper->log();
  EXPECT_GT(no_scans->last_scan_age_s, 3.0f);
  EXPECT_TRUE(mapper->stop());
  log = mapper->log();
  EXPECT_EQ(occurrences(log, "poses arrive on POSE but no scan on VELODYNE_SCAN"), 1U) << log;
  EXPECT_EQ(occurrences(log, "scans arrive on VELODYNE_SCAN but no pose on POSE"), 1U) << log;
}

// A burst of scans (a log played fast) into a queue of one, each scan costly at 0.05 m: the scans the worker
// cannot take in time are dropped as behind and said in one warning that names the count and what makes a
// scan cheaper; a scan larger than the queue's points alone is dropped and named.
TEST_F(MapperInputsTest, AMapperFallingBehindSaysSoInOneWarningAndAScanTooLargeForTheQueueIsNamed) {
  const std::string url = ogf::testing::loopbackUdpmUrl(86);
  auto mapper = startMapper(url,
                            "static_pose: {translation: [1.5, 0, 0.5]}\nmap: {resolution: 0.05}\nfusion:\n"
                            "  max_pending_scans: 1\n  max_pending_points: 20000\n",
                            {"--static", "--in-memory"});
  ASSERT_TRUE(mapper->reportsStatus(10s));
  lcm::LCM lcm(url);
  constexpr int kScans = 40;
  const std::int64_t t0 = wallUtime() - (kScans + 1) * 100'000;  // dated in the past, as a log's are
  for (int i = 0; i < kScans; ++i) {
    const auto scan = fixedSensorScan(i, t0 + i * 100'000, 15000);
    lcm.publish("VELODYNE_SCAN", &scan);
  }
  const auto settled = [](const Status& s) {
    return s.scans_in > 0 && s.scans_mapped + s.scans_dropped_behind == s.scans_in;
  };
  // Settled on every scan sent, or on those the bus delivered.
  auto burst =
      mapper->waitForStatus([&](const Status& s) { return s.scans_in == kScans && settled(s); }, 20s);
  if (!burst) burst = mapper->waitForStatus(settled, 5s);
  ASSERT_TRUE(burst) << mapper->log();
  EXPECT_GT(burst->scans_dropped_behind, 0)
      << "the burst is faster than mapping at 0.05 m: " << mapper->log();
  EXPECT_EQ(burst->scans_dropped_no_pose + burst->scans_refused_time, 0);

  const auto large = fixedSensorScan(kScans, t0 + kScans * 100'000, 30000);
  lcm.publish("VELODYNE_SCAN", &large);
  const auto after =
      mapper->waitForStatus([&](const Status& s) { return s.scans_in > burst->scans_in && settled(s); }, 30s);
  ASSERT_TRUE(after) << mapper->log();
  EXPECT_EQ(after->scans_dropped_behind, burst->scans_dropped_behind + 1);
  EXPECT_EQ(after->scans_mapped, burst->scans_mapped);
  EXPECT_TRUE(mapper->stop());
  const std::string log = mapper->log();
  EXPECT_EQ(occurrences(log, "falling behind: "), 1U)
      << "one warning for the burst, within its 10 s: " << log;
  EXPECT_TRUE(
      std::regex_search(log, std::regex("falling behind: .* \\([1-9][0-9]* so far, scans_dropped_behind; "
                                        "fusion\\.max_pending_scans 1\\)")))
      << log;
  EXPECT_NE(log.find("filter.stencil_manhattan_radius: 0"), std::string::npos) << log;
  EXPECT_NE(log.find("scan seq 40 has 30000 points, more than fusion.max_pending_points (20000)"),
            std::string::npos)
      << log;
}

// The driver holds a partial scan while the sensor is silent and publishes it, dated before the pause, when
// packets come again; the sensor's clock ran on meanwhile.
TEST_F(MapperInputsTest, NoScanIsRefusedAfterAPauseLongerThanMaxTimeAheadAndAStaleScanDatedBeforeIt) {
  const std::string url = ogf::testing::loopbackUdpmUrl(83);
  auto mapper = startMapper(url, "", {"--static", "--in-memory"});
  ASSERT_TRUE(mapper->reportsStatus(10s));
  lcm::LCM lcm(url);
  std::int64_t seq = 0;
  const auto scanNow = [&](int points = 1500) {
    const auto s = fixedSensorScan(seq++, wallUtime(), points);
    lcm.publish("VELODYNE_SCAN", &s);
    std::this_thread::sleep_for(100ms);
    return s;
  };
  ogf::lidar_scan_t last;
  for (int k = 0; k < 20; ++k) last = scanNow();
  std::this_thread::sleep_for(12s);  // fusion.max_time_ahead_s is 10 s
  const auto stale = fixedSensorScan(seq++, last.device_utime_end + 1'000, 300);
  lcm.publish("VELODYNE_SCAN", &stale);
  for (int k = 0; k < 20; ++k) scanNow();
  const auto done =
      mapper->waitForStatus([&](const Status& s) { return s.scans_in == seq && s.scans_mapped == seq; }, 20s);
  const auto s = mapper->latestStatus();
  ASSERT_TRUE(s);
  EXPECT_TRUE(done) << "scans in " << s->scans_in << " mapped " << s->scans_mapped << " of " << seq << "\n"
                    << mapper->log();
  EXPECT_EQ(s->scans_refused_time, 0) << mapper->log();
  EXPECT_EQ(s->clock_jumps, 0) << mapper->log();
  EXPECT_TRUE(mapper->stop());
  EXPECT_EQ(mapper->log().find("refused"), std::string::npos) << mapper->log();
}

TEST_F(MapperInputsTest, TheMapIdTheLogSaysAtARestartIsTheOneMapQueriesAnswer) {
  const std::string url = ogf::testing::loopbackUdpmUrl(84);
  const std::vector<std::string> state{"--state-dir", (dir_ / "state").string()};
  {
    auto mapper = startMapper(url, "", state, "first.log");
    ASSERT_TRUE(mapper->reportsStatus(10s));
    lcm::LCM lcm(url);
    for (int i = 0; i < 10; ++i) {
      const auto step = ogf::testing::feedStep(i, 800);
      for (const auto& p : step.poses) lcm.publish("POSE", &p);
      lcm.publish("VELODYNE_SCAN", &step.scan);
      std::this_thread::sleep_for(50ms);
    }
    ASSERT_TRUE(mapper->waitForStatus([](const Status& s) { return s.scans_mapped >= 8; }, 20s)) << mapper->log();
    ASSERT_TRUE(mapper->stop());
  }
  auto mapper = startMapper(url, "", state, "second.log");
  ASSERT_TRUE(mapper->waitForStatus([](const Status& s) { return s.delta_seq >= 8; }, 10s)) << mapper->log();
  std::smatch restored;
  const std::string log = mapper->log();
  ASSERT_TRUE(std::regex_search(log, restored, std::regex("restored map (-?[0-9]+) at seq"))) << log;
  auto [rc, out] = query(url, {"box", "-5", "-4", "0", "5", "4", "2"});
  ASSERT_EQ(rc, 0) << out;
  std::smatch answered;
  ASSERT_TRUE(std::regex_search(out, answered, std::regex("map_id (-?[0-9]+)"))) << out;
  EXPECT_EQ(restored[1].str(), answered[1].str()) << log << out;
  EXPECT_TRUE(mapper->stop());
}

}  // namespace
