// ogf-mapper as a real process on real LCM (udpm on loopback):
// - ogf-map-client rebuilds exactly the daemon's published map over 1000 scans although the daemon drops
//   a share of its delta updates (gap injection): the client notices every gap and recovers by keyframe;
// - after kill -9 at random instants the restarted daemon resumes with exactly the map an uninterrupted
//   run has at the same update (same filter checksum) and never behind what it had acknowledged, also
//   while regions of the map are paged out to the state directory and back;
// - under a small byte budget on the delta channel, cells wait and go out later, and the client stays
//   consistent;
// - every status sent while scans are mapped gives the checksum, delta seq, measurements and sensor
//   position of exactly the scans it counts as mapped.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "support/file_text.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/message_log.hpp"
#include "ogf/fusion/pose_buffer.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "scan_feeder.hpp"
#include "support/multicast.hpp"
#include "support/output_field.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::outputField;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using ogf::testing::kMapperStatusChannel;

const std::string kBin = OGF_BIN_DIR;

// A feed step on the bus: its odometry, then its scan.
void publishStep(lcm::LCM& lcm, const ogf::testing::FeedStep& step) {
  for (const auto& p : step.poses) lcm.publish("POSE", &p);
  lcm.publish("VELODYNE_SCAN", &step.scan);
}

// Waits, up to `max_waits` times 5 ms, while the daemon has 3 or more scans in hand (received, neither
// mapped nor dropped), so a fast feed does not overrun its queue.
void waitWhileScansInHand(const Mapper& mapper, int max_waits) {
  for (int w = 0; w < max_waits; ++w) {
    const auto s = mapper.latestStatus();
    if (!s || s->scans_in - s->scans_mapped - s->scans_dropped_behind - s->scans_dropped_no_pose < 3) return;
    std::this_thread::sleep_for(5ms);
  }
}

class MapperDaemonTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-mapper-it");
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

std::string lastLine(const std::string& text) {
  auto end = text.find_last_not_of('\n');
  if (end == std::string::npos) return {};
  const auto begin = text.rfind('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end - (begin == std::string::npos ? 0 : begin + 1) + 1);
}

// The client follows `scans` scans of a daemon started with `where` (--in-memory, or a state directory)
// that drops 3 % of its delta updates.
void clientRebuildsTheDaemonsMap(const fs::path& dir, int channel, int scans, const std::vector<std::string>& where) {
  const std::string url = ogf::testing::loopbackUdpmUrl(channel);
  std::vector<std::string> args{kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir / "mapper.yaml").string(),
                                "--test-drop-deltas", "0.03", "--keyframe-interval", "1000", "--log-level", "warn"};
  args.insert(args.end(), where.begin(), where.end());
  Mapper mapper(args, (dir / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  ChildProcess client({kBin + "/ogf-map-client", "--lcm-url", url, "--idle-exit", "3", "--duration", "300",
                       "--log-level", "warn"},
                      (dir / "client.log").string());
  std::this_thread::sleep_for(300ms);

  lcm::LCM lcm(url);
  for (int i = 0; i < scans; ++i) {
    publishStep(lcm, ogf::testing::feedStep(i, 400));
    // Pace like a fast replay; wait whenever the daemon has 3 or more scans in hand.
    std::this_thread::sleep_for(2ms);
    waitWhileScansInHand(mapper, 200);
  }
  const auto done = mapper.waitForStatus(
      [scans](const ogf::mapper_status_t& s) {
        return s.scans_in == scans && s.scans_mapped + s.scans_dropped_behind + s.scans_dropped_no_pose == scans;
      },
      60s);
  ASSERT_TRUE(done) << mapper.log();
  EXPECT_EQ(done->scans_rejected, 0);
  // A last update dropped by the injection is invisible until something follows it: ask for a keyframe,
  // as a client that just started would.
  ogf::map_request_t req{};
  req.requester = "test";
  req.last_seq = -1;
  lcm.publish("OGF_MAP_REQUEST", &req);

  const auto rc = client.wait(120s);
  ASSERT_TRUE(rc.has_value()) << client.log();
  EXPECT_EQ(*rc, 0);
  const std::string line = lastLine(client.log());
  SCOPED_TRACE(line);
  EXPECT_EQ(outputField(line, "consistent"), "yes");
  EXPECT_EQ(std::stoll(outputField(line, "seq")), done->delta_seq);
  EXPECT_FALSE(outputField(line, " published_checksum").empty());
  EXPECT_EQ(outputField(line, " published_checksum"), outputField(line, "mapper_published_checksum"));
  EXPECT_GT(std::stoll(outputField(line, "gaps")), 0) << "the injection should have made gaps";
  EXPECT_GE(std::stoll(outputField(line, "keyframes")), 1);
  EXPECT_EQ(outputField(line, "malformed"), "0");
  EXPECT_TRUE(mapper.stop());
}

TEST_F(MapperDaemonTest, ClientRebuildsTheDaemonsMapOver1000ScansWithGapsInjected) {
  clientRebuildsTheDaemonsMap(dir_, 31, 1000, {"--in-memory"});
}

// Regions beyond 1 m go to their pages after every scan with their published cells, and come back: the
// client's map and checksum still equal the daemon's, keyframes (with the paged-out cells read from their
// pages) included.
// With deltas.max_bytes_per_s far below what the scans change, cells wait in the mapper (the status counts
// them, never more than deltas.max_wait_s of the rate; the changes beyond mark their slabs stale) and go
// out in later updates, and the client, applying every message, ends with the mapper's published checksum
// at its last update.
TEST_F(MapperDaemonTest, CellsOverTheDeltaBudgetWaitAndTheClientEndsWithTheMappersChecksum) {
  const fs::path dir = dir_;
  // 30 kB/s: about 150 cells per 100 ms scan, against thousands of changed cells in the first scans.
  std::ofstream(dir / "mapper.yaml") << "status_interval_s: 0.1\n"
                                        "deltas:\n"
                                        "  max_bytes_per_s: 30000\n"
                                        "  burst_s: 0.1\n"
                                        "  max_wait_s: 0.5\n";
  // 0.5 s of 30 kB/s, 19 bytes a cell beyond each message's header.
  const std::int64_t max_waiting = 15000 / 19;
  const std::string url = ogf::testing::loopbackUdpmUrl(44);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir / "mapper.yaml").string(), "--in-memory",
                 "--keyframe-interval", "1000", "--log-level", "warn"},
                (dir / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  ChildProcess client({kBin + "/ogf-map-client", "--lcm-url", url, "--idle-exit", "3", "--duration", "300",
                       "--log-level", "warn"},
                      (dir / "client.log").string());
  std::this_thread::sleep_for(300ms);

  lcm::LCM lcm(url);
  const int scans = 300;
  std::int64_t most_waiting = 0;
  for (int i = 0; i < scans; ++i) {
    const auto step = ogf::testing::feedStep(i, 1500);
    for (const auto& p : step.poses) lcm.publish("POSE", &p);
    lcm.publish("VELODYNE_SCAN", &step.scan);
    std::this_thread::sleep_for(100ms);  // the scan rate: the budget accrues in real time
    if (const auto s = mapper.latestStatus()) most_waiting = std::max(most_waiting, s->delta_cells_waiting);
  }
  const auto done = mapper.waitForStatus(
      [scans](const ogf::mapper_status_t& s) {
        return s.scans_in == scans && s.scans_mapped + s.scans_dropped_behind + s.scans_dropped_no_pose == scans;
      },
      60s);
  ASSERT_TRUE(done) << mapper.log();
  EXPECT_GT(most_waiting, 0) << "the budget should have held cells back";
  EXPECT_LE(most_waiting, max_waiting);
  EXPECT_GT(done->delta_cells_overflowed, 0) << "the scans' changes should have outrun the waiting cells";
  EXPECT_GT(done->delta_cells_sent, 0);
  EXPECT_GT(done->delta_bytes_sent, 0);

  const auto rc = client.wait(120s);
  ASSERT_TRUE(rc.has_value()) << client.log();
  EXPECT_EQ(*rc, 0);
  const std::string line = lastLine(client.log());
  SCOPED_TRACE(line);
  EXPECT_EQ(outputField(line, "consistent"), "yes");
  EXPECT_EQ(std::stoll(outputField(line, "seq")), done->delta_seq);
  EXPECT_EQ(outputField(line, " published_checksum"), outputField(line, "mapper_published_checksum"));
  EXPECT_EQ(outputField(line, "gaps"), "0");
  EXPECT_EQ(outputField(line, "malformed"), "0");
  EXPECT_TRUE(mapper.stop());
}

TEST_F(MapperDaemonTest, ClientRebuildsTheDaemonsMapWhileRegionsArePagedOutAndIn) {
  std::ofstream(dir_ / "mapper.yaml", std::ios::app) << "page_out_distance_m: 1.0\n";
  clientRebuildsTheDaemonsMap(dir_, 36, 300, {"--state-dir", (dir_ / "state").string()});
  const std::string log = ogf::testing::fileText(dir_ / "mapper.log");
  EXPECT_NE(log.find("within the scans' reach"), std::string::npos) << "regions should churn: " << log;
  EXPECT_EQ(log.find("are lost"), std::string::npos) << log;
}

TEST_F(MapperDaemonTest, EveryStatusWhileMappingGivesTheChecksumAndCountsOfTheSameScans) {
  constexpr int kScans = 40;
  constexpr int kPoints = 1500;
  // The same scans offline: after k scans, the filter checksum, the measurements and the sensor's position.
  struct AfterScans {
    std::uint64_t checksum = 0;
    std::int64_t measurements = 0;
    Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  };
  std::vector<AfterScans> after(1);  // [k] after k scans
  {
    ogf::pipeline::MapperConfig cfg;  // the daemon's defaults
    auto offline = ogf::pipeline::ScanMapper::create(cfg);
    ASSERT_TRUE(offline.ok());
    ogf::fusion::PoseBuffer poses(cfg.fusion.pose_buffer);
    after[0].checksum = offline->filter().checksum();
    for (int i = 0; i < kScans; ++i) {
      const auto step = ogf::testing::feedStep(i, kPoints);
      for (const auto& p : step.poses)
        poses.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                      Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
      const auto& sc = step.scan;
      if (offline->measure({sc.device_utime_start, sc.x, sc.y, sc.z, sc.time_offset_ns}, poses) !=
          ogf::fusion::PoseCoverage::kCovered)
        break;  // the last scans may wait for odometry beyond their end
      offline->apply(offline->measurements());
      after.push_back({offline->filter().checksum(),
                       after.back().measurements + static_cast<std::int64_t>(offline->measurements().size()),
                       offline->sensorOrigin()});
    }
  }
  ASSERT_GE(after.size(), static_cast<std::size_t>(kScans - 1));

  // Statuses every 2 ms: many fall while the worker maps a scan, and some go out before it can answer.
  std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.002\n";
  const std::string url = ogf::testing::loopbackUdpmUrl(38);
  ogf::testing::MessageLog<ogf::mapper_status_t> statuses(url, kMapperStatusChannel);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "mapper.yaml").string(), "--in-memory",
                 "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  lcm::LCM lcm(url);
  // A scan every 15 ms for 0.6 s, waiting whenever the daemon has 3 or more in hand (a loaded machine must
  // not make it drop one: the counts would no longer name the scans 0..k-1).
  for (int i = 0; i < kScans; ++i) {
    publishStep(lcm, ogf::testing::feedStep(i, kPoints));
    std::this_thread::sleep_for(15ms);
    waitWhileScansInHand(mapper, 400);
  }
  const auto done = mapper.waitForStatus(
      [](const ogf::mapper_status_t& s) {
        return s.scans_in == kScans && s.scans_mapped + s.scans_dropped_no_pose + s.scans_dropped_behind == kScans;
      },
      30s);
  ASSERT_TRUE(done) << mapper.log();
  ASSERT_EQ(done->scans_dropped_behind, 0) << "a scan dropped leaves a gap in the scans counted as mapped";
  ASSERT_EQ(done->scans_mapped + 1, static_cast<std::int64_t>(after.size()) + done->scans_dropped_no_pose);

  std::set<std::int64_t> counts_seen;
  for (const auto& s : statuses.messages()) {
    const std::int64_t k = s.scans_mapped;
    if (k == 0) continue;
    SCOPED_TRACE("status of " + std::to_string(k) + " scans mapped");
    ASSERT_LT(k, static_cast<std::int64_t>(after.size()));
    const AfterScans& expected = after[static_cast<std::size_t>(k)];
    counts_seen.insert(k);
    EXPECT_EQ(static_cast<std::uint64_t>(s.filter_checksum), expected.checksum);
    EXPECT_EQ(s.delta_seq, k);
    EXPECT_EQ(s.measurements, expected.measurements);
    ASSERT_EQ(s.num_sources, 1);
    const auto& source = s.sources[0];
    EXPECT_EQ(source.scans_mapped, k);
    EXPECT_EQ(source.measurements, expected.measurements);
    ASSERT_GT(source.trail_size, 0);
    const auto& at = source.trail.back();
    EXPECT_NEAR(at[0], expected.sensor.x(), 1e-4);
    EXPECT_NEAR(at[1], expected.sensor.y(), 1e-4);
    EXPECT_NEAR(at[2], expected.sensor.z(), 1e-4);
  }
  // Statuses before the last scan was mapped, not only the final one.
  EXPECT_GE(counts_seen.size(), 3U) << "statuses of " << counts_seen.size() << " distinct scan counts";
  EXPECT_TRUE(mapper.stop());
}

// Kills the daemon (kill -9) at random instants over `rounds` rounds of scans, restarting it each time on its
// state directory; `config` is added to its configuration.
void killNineAtRandomInstants(const fs::path& dir, int channel, const std::string& config) {
  const int rounds = std::getenv("OGF_KILL_ROUNDS") ? std::atoi(std::getenv("OGF_KILL_ROUNDS")) : 5;
  const std::string url = ogf::testing::loopbackUdpmUrl(channel);
  lcm::LCM lcm(url);

  // The reference: the same scans through the same pipeline, uninterrupted; checksum after each update.
  ogf::pipeline::MapperConfig cfg;  // the daemon's defaults
  auto reference = ogf::pipeline::ScanMapper::create(cfg);
  ASSERT_TRUE(reference.ok());
  ogf::fusion::PoseBuffer ref_poses(cfg.fusion.pose_buffer);
  std::vector<std::uint64_t> ref_checksum{reference->filter().checksum()};  // [k] after k updates
  const auto extendReference = [&](int upto) {
    while (static_cast<int>(ref_checksum.size()) <= upto) {
      const int i = static_cast<int>(ref_checksum.size()) - 1;
      const auto step = ogf::testing::feedStep(i, 800);
      for (const auto& p : step.poses)
        ref_poses.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                          Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
      const auto& s = step.scan;
      ASSERT_EQ(reference->measure({s.device_utime_start, s.x, s.y, s.z, s.time_offset_ns}, ref_poses),
                ogf::fusion::PoseCoverage::kCovered);
      reference->apply(reference->measurements());
      ref_checksum.push_back(reference->filter().checksum());
    }
  };

  // Update k is scan k-1 only if the daemon maps every scan. A round publishes a scan every 15 ms, faster
  // than a loaded machine maps them (a new map's first scans took ~75 ms each here), and with the default
  // 10-scan queue the daemon then drops the oldest waiting one, as it should when it falls behind
  // (scans_dropped_behind): the restarted map lacks that scan and differs from the reference. A queue that
  // holds a whole round makes the scans wait for the mapper instead, as in the fault tests' kill -9.
  constexpr int kMaxScansPerRound = 25;
  std::ofstream(dir / "mapper.yaml", std::ios::app)
      << "fusion:\n  max_pending_scans: " << kMaxScansPerRound << "\n" << config;

  // The first status of a restarted daemon, never one the killed daemon sent just before the kill: its
  // counters run from its start, and no scan is sent before this status.
  const auto fromThisDaemon = [](const ogf::mapper_status_t& s) { return s.scans_in == 0; };

  std::mt19937 rng(20261121);
  std::int64_t acknowledged = 0;
  int next_scan = 0;
  for (int round = 0; round < rounds; ++round) {
    Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir / "state").string(), "--config",
                   (dir / "mapper.yaml").string(), "--snapshot-interval", "0.4", "--log-level", "warn"},
                  (dir / ("mapper-" + std::to_string(round) + ".log")).string(), url, kMapperStatusChannel);
    const auto first = mapper.waitForStatus(fromThisDaemon, 10s);
    ASSERT_TRUE(first) << mapper.log();
    const std::int64_t restored = first->delta_seq;
    SCOPED_TRACE("round " + std::to_string(round) + " restored seq " + std::to_string(restored));
    EXPECT_GE(restored, acknowledged) << "an acknowledged update was lost";
    extendReference(static_cast<int>(restored));
    EXPECT_EQ(static_cast<std::uint64_t>(first->filter_checksum), ref_checksum[static_cast<std::size_t>(restored)])
        << "the restarted map differs from an uninterrupted run at the same update";
    EXPECT_TRUE(first->persistence_ok) << first->persistence_error;

    // Continue from the scan after the restored update: every scan so far was mapped, so update k is scan k-1.
    next_scan = static_cast<int>(restored);
    if (next_scan > 0) {
      for (const auto& p : ogf::testing::feedStep(next_scan - 1, 800).poses) lcm.publish("POSE", &p);
    }
    const int count = std::uniform_int_distribution<int>(5, kMaxScansPerRound)(rng);
    for (int k = 0; k < count; ++k, ++next_scan) {
      publishStep(lcm, ogf::testing::feedStep(next_scan, 800));
      std::this_thread::sleep_for(15ms);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(std::uniform_int_distribution<int>(0, 150)(rng)));
    if (const auto s = mapper.latestStatus()) {
      acknowledged = s->delta_seq;
      EXPECT_EQ(s->scans_dropped_behind + s->scans_dropped_no_pose + s->scans_late, 0)
          << "the daemon left out a scan, so the next restart cannot match the reference";
    }
    ASSERT_TRUE(mapper.kill());
  }
  // And a clean stop keeps everything: the final snapshot then a restart at the same seq.
  {
    Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir / "state").string(), "--config",
                   (dir / "mapper.yaml").string(), "--log-level", "warn"},
                  (dir / "mapper-final.log").string(), url, kMapperStatusChannel);
    const auto s = mapper.waitForStatus(fromThisDaemon, 10s);
    ASSERT_TRUE(s) << mapper.log();
    extendReference(static_cast<int>(s->delta_seq));
    EXPECT_EQ(static_cast<std::uint64_t>(s->filter_checksum), ref_checksum[static_cast<std::size_t>(s->delta_seq)]);
    EXPECT_TRUE(mapper.stop());
  }
}

TEST_F(MapperDaemonTest, KillNineAtRandomInstantsResumesExactlyTheAcknowledgedMap) {
  killNineAtRandomInstants(dir_, 32, "");
}

TEST_F(MapperDaemonTest, KillNineWhileRegionsArePagedOutAndInResumesExactlyTheAcknowledgedMap) {
  // Regions 1 m beyond the robot leave memory after a scan and come back for the next one that reaches
  // them, so every snapshot names pages and every restart reads them back (the journal's scans too).
  killNineAtRandomInstants(dir_, 35, "page_out_distance_m: 1.0\n");
  std::size_t pages = 0;
  for (const auto& e : fs::directory_iterator(dir_ / "state" / "pages")) pages += e.path().extension() == ".ogfp";
  EXPECT_GT(pages, 0u) << "the snapshots must have named pages";
}

TEST_F(MapperDaemonTest, ScanMatchingCorrectsDriftingOdometryAndPublishesTheCorrectedPoses) {
  const std::string url = ogf::testing::loopbackUdpmUrl(33);
  std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\npose_correction: {mode: scan-match}\n";
  ogf::testing::MessageLog<ogf::odometry_t> corrected(url, "POSE_CORRECTED");
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config", (dir_ / "mapper.yaml").string(),
                 "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));

  // Odometry that over-reads x by 0.05 m per second (the robot itself moves at about 0.08 m/s), while the scans come from the true poses.
  constexpr int kScans = 60;
  constexpr double kDriftPerSecond = 0.05;
  std::map<std::int64_t, std::pair<double, double>> truth;
  lcm::LCM lcm(url);
  std::int64_t t_first = -1;
  for (int i = 0; i < kScans; ++i) {
    auto step = ogf::testing::feedStep(i, 1500);
    for (auto& p : step.poses) {
      if (t_first < 0) t_first = p.utime;
      truth[p.utime] = {p.position[0], p.position[1]};
      p.position[0] += kDriftPerSecond * static_cast<double>(p.utime - t_first) * 1e-6;
    }
    publishStep(lcm, step);
    std::this_thread::sleep_for(20ms);
    for (int w = 0; w < 400; ++w) {
      const auto s = mapper.latestStatus();
      if (!s || s->scans_in - s->scans_mapped - s->scans_dropped_behind - s->scans_dropped_no_pose < 2) break;
      std::this_thread::sleep_for(5ms);
    }
  }
  const auto done = mapper.waitForStatus([](const ogf::mapper_status_t& s) { return s.scans_mapped == kScans; }, 60s);
  ASSERT_TRUE(done) << mapper.log();
  std::this_thread::sleep_for(300ms);
  const auto poses = corrected.messages();
  ASSERT_EQ(static_cast<int>(poses.size()), kScans) << "one corrected pose per mapped scan";
  // The last corrected pose against the truth at its time, and the odometry's error there.
  const auto& last = poses.back();
  auto it = truth.lower_bound(last.utime);
  ASSERT_NE(it, truth.end());
  const double odometry_error = kDriftPerSecond * static_cast<double>(it->first - t_first) * 1e-6;
  const double corrected_error = std::hypot(last.position[0] - it->second.first, last.position[1] - it->second.second);
  EXPECT_GT(odometry_error, 0.25);
  EXPECT_LT(corrected_error, 0.3 * odometry_error) << "odometry error " << odometry_error << " m";
  EXPECT_EQ(last.frame_id, "map");
  std::printf("corrected error %.3f m, odometry error %.3f m\n", corrected_error, odometry_error);
  EXPECT_TRUE(mapper.stop());
}

// ogf-map-query against the running daemon: a box over the room and cells on a wall and in the air are
// answered from the map it holds; malformed and oversized requests are refused and counted, never stop
// it; save, export and reset signed with the key do what they say (the export in the export directory,
// the old map kept on disk) and mapping goes on after them.
TEST_F(MapperDaemonTest, MapServicesAnswerQueriesAndCommandsWhileTheDaemonMaps) {
  const std::string url = ogf::testing::loopbackUdpmUrl(34);
  const std::string key = (dir_ / "command.key").string();
  {
    ChildProcess keygen({kBin + "/ogf-map-query", "keygen", key}, (dir_ / "keygen.log").string());
    ASSERT_EQ(keygen.wait(10s).value_or(-1), 0) << keygen.log();
  }
  std::ofstream(dir_ / "mapper.yaml", std::ios::app)
      << "services: {commands_enabled: true, key_file: " << key << ", export_min_free_bytes: 0}\n";
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir_ / "state").string(), "--config",
                 (dir_ / "mapper.yaml").string(), "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(10s));
  lcm::LCM lcm(url);
  const auto feed = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      publishStep(lcm, ogf::testing::feedStep(i, 1500));
      std::this_thread::sleep_for(20ms);
    }
    // The last scan may wait for odometry beyond its end and be dropped; the others are mapped.
    return mapper.waitForStatus(
        [&](const ogf::mapper_status_t& s) {
          return s.scans_in == to && s.scans_mapped + s.scans_dropped_no_pose + s.scans_dropped_behind == to &&
                 s.scans_mapped >= to - 2;
        },
        30s);
  };
  const auto fed = feed(0, 30);
  ASSERT_TRUE(fed) << mapper.log()
                   << (mapper.latestStatus() ? " mapped " + std::to_string(mapper.latestStatus()->scans_mapped) : "");
  int n = 0;
  const auto query = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {kBin + "/ogf-map-query", "--lcm-url", url});
    ChildProcess q(args, (dir_ / ("query" + std::to_string(++n) + ".log")).string());
    const auto rc = q.wait(20s);
    return std::make_pair(rc.value_or(-1), q.log());
  };

  // The room is 10 m x 8 m, walls at x = ±5 and y = ±4, 2 m high.
  auto [rc, out] = query({"box", "-5", "-4", "0", "5", "4", "2"});
  ASSERT_EQ(rc, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("known_volume_m3 (\\S+) unknown_volume_m3 (\\S+) mean_entropy_bits (\\S+)")))
      << out;
  EXPECT_GT(std::stod(m[1]), 20.0) << out;   // most of the 160 m3 room is known
  EXPECT_LT(std::stod(m[3]), 0.9) << out;     // and the map is surer than its prior (1 bit)
  std::tie(rc, out) = query({"cell", "5.05", "0.1", "1.0", "3.0", "0.1", "0.5"});  // the sensor is 0.5 m up
  ASSERT_EQ(rc, 0) << out;
  EXPECT_TRUE(std::regex_search(out, std::regex("5\\.050 +0\\.100 +1\\.000 +\\S+ +occ"))) << out;
  EXPECT_TRUE(std::regex_search(out, std::regex("3\\.000 +0\\.100 +0\\.500 +\\S+ +free"))) << out;

  // Refused, counted, and the daemon goes on.
  std::tie(rc, out) = query({"box", "-1000", "-1000", "-10", "1000", "1000", "10"});
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("exceed the limit"), std::string::npos) << out;
  const char junk[] = "not a map_query_t at all";
  lcm.publish("OGF_MAP_QUERY", junk, sizeof junk);
  EXPECT_TRUE(mapper.waitForStatus([](const ogf::mapper_status_t& s) { return s.service_requests_refused >= 2; }, 10s))
      << mapper.log();
  std::tie(rc, out) = query({"--key", key, "export", "ply", (dir_ / "map.ply").string()});
  EXPECT_EQ(rc, 1) << out;

  std::tie(rc, out) = query({"--key", key, "export", "ply", "map.ply"});
  ASSERT_EQ(rc, 0) << out;
  EXPECT_GT(fs::file_size(dir_ / "state" / "exports" / "map.ply"), 1000u);
  std::tie(rc, out) = query({"--key", key, "save"});
  EXPECT_EQ(rc, 0) << out;
  std::tie(rc, out) = query({"--key", key, "reset"});
  ASSERT_EQ(rc, 0) << out;
  bool kept = false;
  for (const auto& e : fs::directory_iterator(dir_ / "state")) {
    kept |= e.path().filename().string().rfind("reset-", 0) == 0 && fs::exists(e.path() / "snapshot.ogfs");
  }
  EXPECT_TRUE(kept) << "the map before the reset stays on disk";
  std::tie(rc, out) = query({"box", "-5", "-4", "0", "5", "4", "2"});
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("occupied 0 free 0"), std::string::npos) << "a reset map knows nothing: " << out;

  // Mapping goes on into the new map.
  EXPECT_TRUE(feed(30, 40)) << mapper.log();
  std::tie(rc, out) = query({"box", "-5", "-4", "0", "5", "4", "2"});
  ASSERT_EQ(rc, 0) << out;
  EXPECT_EQ(out.find("occupied 0 free 0"), std::string::npos) << out;
  EXPECT_TRUE(mapper.stop());
}

}  // namespace
