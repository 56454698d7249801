// ogf-mapper with several sources (the configuration's `sources:` list), a real process on real LCM (udpm on
// loopback), the test publishing the scans and the odometry itself:
// - two lidars on one robot, one of them mounted backwards: both fold into the map an offline ScanMapper
//   makes of the same scans with each source's extrinsic, and the status counts each by name;
// - two robots, each placed with its own odometry in the shared frame: the same, and each sensor's trail
//   follows its own robot;
// - a source whose scans are dated in 2100, one sending forged bytes and a silent one never stop a working
//   one: its scans are all mapped, to the map it makes alone, and the status names the faulty sources;
// - a source of raw packets decoded in the mapper maps a real capture as the driver's scans of it do.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <ogf/mapper_status_t.hpp>
#include <string>
#include <thread>

#include "offline_checksum.hpp"
#include "ogf/fusion/pose_buffer.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "scan_feeder.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Status = ogf::mapper_status_t;
using Mapper = ogf::testing::DaemonProcess<Status>;
using ogf::testing::FeedStep;

const std::string kBin = OGF_BIN_DIR;
constexpr int kSteps = 15;

// The scan as a sensor turned half round about z (quaternion w 0, z 1) sees it: x and y negated, exactly.
ogf::lidar_scan_t turnedHalfRound(ogf::lidar_scan_t scan) {
  for (auto& x : scan.x) x = -x;
  for (auto& y : scan.y) y = -y;
  return scan;
}

// The odometry of a robot `dx` metres further along x.
std::vector<ogf::odometry_t> shifted(std::vector<ogf::odometry_t> poses, double dx) {
  for (auto& p : poses) p.position[0] += dx;
  return poses;
}

const ogf::source_status_t* sourceNamed(const Status& s, const std::string& name) {
  for (const auto& src : s.sources)
    if (src.name == name) return &src;
  return nullptr;
}

// One source's scans and its robot's poses, for the offline map.
struct OfflineFeed {
  std::vector<FeedStep> steps;
  Eigen::Isometry3d body_from_sensor = Eigen::Isometry3d::Identity();
  int robot = 0;  // index of its pose buffer
};

// The map a ScanMapper with the daemon's default configuration makes of the feeds' scans, step by step and
// feed by feed in the order given (the order the daemon maps them: the oldest scan first, ties in the
// order of the sources), each placed with its extrinsic and its robot's poses. A hit is held through
// free_release_scans free scans for each source, as the daemon holds it.
std::uint64_t offlineChecksumOfFeeds(const std::vector<OfflineFeed>& feeds, int robots) {
  ogf::pipeline::MapperConfig cfg;
  cfg.filter.freeReleaseCount *= static_cast<int>(feeds.size());
  auto mapper = ogf::pipeline::ScanMapper::create(cfg);
  if (!mapper.ok()) return 0;
  std::vector<ogf::fusion::PoseBuffer> poses(static_cast<std::size_t>(robots),
                                             ogf::fusion::PoseBuffer(cfg.fusion.pose_buffer));
  for (std::size_t i = 0; i < feeds.front().steps.size(); ++i) {
    for (const auto& feed : feeds) {
      auto& buffer = poses[static_cast<std::size_t>(feed.robot)];
      for (const auto& p : feed.steps[i].poses)
        buffer.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                       Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
    }
    for (const auto& feed : feeds) {
      const auto& s = feed.steps[i].scan;
      mapper->setBodyFromSensor(feed.body_from_sensor);
      if (mapper->measure({s.device_utime_start, s.x, s.y, s.z, s.time_offset_ns},
                          poses[static_cast<std::size_t>(feed.robot)]) != ogf::fusion::PoseCoverage::kCovered)
        return 0;
      mapper->apply(mapper->measurements());
    }
  }
  return mapper->filter().checksum();
}

class MapperSourcesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-mapper-sources");
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  std::unique_ptr<Mapper> startMapper(const std::string& url, const std::string& config,
                                      const std::string& name = "mapper") {
    std::ofstream(dir_ / (name + ".yaml")) << "status_interval_s: 0.1\n" << config;
    return std::make_unique<Mapper>(
        std::vector<std::string>{kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / (name + ".yaml")).string(),
                                 "--in-memory", "--log-level", "info"},
        (dir_ / (name + ".log")).string(), url, ogf::testing::kMapperStatusChannel);
  }
  // Publishes step after step through `publish`, never more than two scans ahead of the mapper.
  static void feed(Mapper& mapper, const std::function<void(int)>& publish) {
    for (int i = 0; i < kSteps; ++i) {
      publish(i);
      std::this_thread::sleep_for(20ms);
      for (int w = 0; w < 400; ++w) {
        const auto s = mapper.latestStatus();
        if (!s || s->scans_in - s->scans_mapped - s->scans_dropped_behind - s->scans_refused_time -
                          s->scans_rejected - s->scans_dropped_no_pose <
                      3)
          break;
        std::this_thread::sleep_for(5ms);
      }
    }
  }

  fs::path dir_;
};

TEST_F(MapperSourcesTest, TwoLidarsOnOneRobotFoldIntoTheOfflineMapOfBothAndAreCountedByName) {
  const std::string url = ogf::testing::loopbackUdpmUrl(101);
  auto mapper = startMapper(url,
                            "sources:\n"
                            "  - {name: front, scan_channel: SCAN_FRONT}\n"
                            "  - name: rear\n"
                            "    scan_channel: SCAN_REAR\n"
                            "    extrinsic: {translation: [0, 0, 0], quaternion: [0, 0, 0, 1]}\n");
  ASSERT_TRUE(mapper->reportsStatus(10s));
  EXPECT_NE(mapper->log().find("mapping 2 sources on"), std::string::npos) << mapper->log();
  lcm::LCM lcm(url);
  OfflineFeed front, rear;
  rear.body_from_sensor = Eigen::Isometry3d(Eigen::Quaterniond(0, 0, 0, 1));
  feed(*mapper, [&](int i) {
    FeedStep step = ogf::testing::feedStep(i);
    for (const auto& p : step.poses) lcm.publish("POSE", &p);
    lcm.publish("SCAN_FRONT", &step.scan);
    FeedStep turned = step;
    turned.scan = turnedHalfRound(step.scan);
    lcm.publish("SCAN_REAR", &turned.scan);
    front.steps.push_back(step);
    rear.steps.push_back(turned);
  });
  const auto done = mapper->waitForStatus([](const Status& s) { return s.scans_mapped == 2 * kSteps; }, 30s);
  ASSERT_TRUE(done) << mapper->log();
  ASSERT_EQ(done->num_sources, 2);
  const auto* f = sourceNamed(*done, "front");
  const auto* r = sourceNamed(*done, "rear");
  ASSERT_TRUE(f && r);
  EXPECT_EQ(f->scans_mapped, kSteps);
  EXPECT_EQ(r->scans_mapped, kSteps);
  EXPECT_EQ(f->robot, "robot");
  EXPECT_EQ(r->scan_channel, "SCAN_REAR");
  EXPECT_EQ(f->pose_channel, "POSE");
  EXPECT_EQ(done->inputs, Status::INPUTS_OK);
  EXPECT_EQ(f->inputs, Status::INPUTS_OK);
  EXPECT_EQ(done->measurements, f->measurements + r->measurements);
  ASSERT_GT(f->trail_size, 0);
  ASSERT_EQ(f->trail_size, r->trail_size);
  for (int k = 0; k < 3; ++k)  // both sensors sit at the body's origin
    EXPECT_FLOAT_EQ(f->trail.back()[static_cast<std::size_t>(k)], r->trail.back()[static_cast<std::size_t>(k)]);
  const std::uint64_t expected = offlineChecksumOfFeeds({front, rear}, 1);
  ASSERT_NE(expected, 0U);
  EXPECT_EQ(static_cast<std::uint64_t>(done->filter_checksum), expected)
      << "the daemon's map is not the offline map of both sources' scans, each with its extrinsic";
  EXPECT_NE(expected, ogf::testing::offlineChecksum(kSteps)) << "the rear scans must add to the map";
  EXPECT_TRUE(mapper->stop());
}

TEST_F(MapperSourcesTest, TwoRobotsArePlacedEachWithItsOwnOdometryInTheSharedFrame) {
  const std::string url = ogf::testing::loopbackUdpmUrl(102);
  auto mapper = startMapper(url,
                            "sources:\n"
                            "  - {name: lidar, robot: r1, scan_channel: SCAN_R1, pose_channel: POSE_R1}\n"
                            "  - {name: lidar2, robot: r2, scan_channel: SCAN_R2, pose_channel: POSE_R2}\n");
  ASSERT_TRUE(mapper->reportsStatus(10s));
  lcm::LCM lcm(url);
  constexpr double kApart = 20.0;  // metres along x between the two robots
  OfflineFeed one, two;
  two.robot = 1;
  feed(*mapper, [&](int i) {
    FeedStep step = ogf::testing::feedStep(i);
    FeedStep other = step;
    other.poses = shifted(step.poses, kApart);
    for (const auto& p : step.poses) lcm.publish("POSE_R1", &p);
    for (const auto& p : other.poses) lcm.publish("POSE_R2", &p);
    lcm.publish("SCAN_R1", &step.scan);
    lcm.publish("SCAN_R2", &other.scan);
    one.steps.push_back(step);
    two.steps.push_back(other);
  });
  const auto done = mapper->waitForStatus([](const Status& s) { return s.scans_mapped == 2 * kSteps; }, 30s);
  ASSERT_TRUE(done) << mapper->log();
  const auto* a = sourceNamed(*done, "lidar");
  const auto* b = sourceNamed(*done, "lidar2");
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->robot, "r1");
  EXPECT_EQ(b->robot, "r2");
  EXPECT_EQ(b->pose_channel, "POSE_R2");
  std::int64_t poses_each = 0;
  for (const auto& step : one.steps) poses_each += static_cast<std::int64_t>(step.poses.size());
  EXPECT_EQ(a->poses_in, poses_each) << "each robot counts its own odometry";
  EXPECT_EQ(b->poses_in, poses_each);
  EXPECT_EQ(done->poses_in, a->poses_in + b->poses_in);
  ASSERT_GT(a->trail_size, 1);
  EXPECT_NEAR(b->trail.back()[0] - a->trail.back()[0], kApart, 1e-3) << "r2's sensor follows r2's odometry";
  EXPECT_NEAR(b->trail.back()[1], a->trail.back()[1], 1e-3);
  const std::uint64_t expected = offlineChecksumOfFeeds({one, two}, 2);
  ASSERT_NE(expected, 0U);
  EXPECT_EQ(static_cast<std::uint64_t>(done->filter_checksum), expected);
  EXPECT_TRUE(mapper->stop());
}

TEST_F(MapperSourcesTest, ASourceDatedIn2100AForgedOneAndASilentOneNeverStopAWorkingOneAndAreNamed) {
  const std::string url = ogf::testing::loopbackUdpmUrl(103);
  auto mapper = startMapper(url,
                            "sources:\n"
                            "  - {name: good, scan_channel: SCAN_GOOD}\n"
                            "  - {name: future, scan_channel: SCAN_FUTURE}\n"
                            "  - {name: forged, scan_channel: SCAN_FORGED}\n"
                            "  - {name: silent, scan_channel: SCAN_SILENT}\n");
  ASSERT_TRUE(mapper->reportsStatus(10s));
  lcm::LCM lcm(url);
  // 2100-01-01 minus the feeder's own epoch: the same scans, 75 years ahead.
  constexpr std::int64_t k2100 = 4'102'444'800'000'000;
  feed(*mapper, [&](int i) {
    const FeedStep step = ogf::testing::feedStep(i);
    for (const auto& p : step.poses) lcm.publish("POSE", &p);
    lcm.publish("SCAN_GOOD", &step.scan);
    ogf::lidar_scan_t future = step.scan;
    const std::int64_t ahead = k2100 - future.device_utime_start;
    for (auto* t : {&future.utime, &future.device_utime_start, &future.device_utime_end, &future.host_utime_start,
                    &future.host_utime_end})
      *t += ahead;
    lcm.publish("SCAN_FUTURE", &future);
    const std::string forged = "not a scan, but 40 bytes of something else";
    lcm.publish("SCAN_FORGED", forged.data(), static_cast<unsigned>(forged.size()));
  });
  const auto done = mapper->waitForStatus(
      [](const Status& s) {
        const auto* silent = sourceNamed(s, "silent");
        return s.scans_mapped == kSteps && silent && silent->inputs == Status::INPUTS_WAITING_FOR_SCANS;
      },
      30s);
  ASSERT_TRUE(done) << mapper->log();
  const auto* good = sourceNamed(*done, "good");
  const auto* future = sourceNamed(*done, "future");
  const auto* forged = sourceNamed(*done, "forged");
  ASSERT_TRUE(good && future && forged);
  EXPECT_EQ(forged->scans_in, kSteps);
  EXPECT_EQ(forged->scans_rejected, kSteps);
  EXPECT_EQ(forged->scans_mapped, 0);
  EXPECT_EQ(good->scans_mapped, kSteps);
  EXPECT_EQ(good->inputs, Status::INPUTS_OK);
  EXPECT_EQ(future->scans_mapped, 0);
  EXPECT_EQ(future->scans_in, kSteps);
  EXPECT_EQ(future->scans_refused_time + future->scans_dropped_no_pose, kSteps)
      << "a scan 75 years ahead is refused for its time, or waits in vain for poses";
  EXPECT_GT(future->scans_refused_time, 0);
  EXPECT_EQ(done->inputs, Status::INPUTS_WAITING_FOR_SCANS) << "the whole is not OK while a source is silent";
  EXPECT_EQ(static_cast<std::uint64_t>(done->filter_checksum), ogf::testing::offlineChecksum(kSteps))
      << "the working source's map is the one it makes alone";
  EXPECT_TRUE(mapper->stop());
  EXPECT_NE(mapper->log().find("source future: scan at"), std::string::npos) << mapper->log();
  EXPECT_NE(mapper->log().find("source forged: scan on SCAN_FORGED ("), std::string::npos) << mapper->log();
  EXPECT_NE(mapper->log().find("source silent: inputs: poses arrive on POSE but no scan on SCAN_SILENT"),
            std::string::npos)
      << mapper->log();
}

TEST_F(MapperSourcesTest, RawPacketsDecodedInTheMapperMapARealCaptureAsTheDriversScansOfItDo) {
  const auto pcap = ogf::testing::sharedFile("data/real/vlp-16-test-90deg-1-50-frames.pcap");
  if (!pcap) GTEST_SKIP() << "shared data absent under " << ogf::testing::sharedDir();
  const std::string url = ogf::testing::loopbackUdpmUrl(104);
  // Two mappers on one bus, each with its own output channels: one maps the driver's scans, the other the
  // raw packets of the same scans.
  const std::string common = "pose_source: static\n";
  auto scans = startMapper(url, common + "sources: [{name: scans, scan_channel: VELODYNE_SCAN}]\n", "scans");
  std::ofstream(dir_ / "packets.yaml") << "status_interval_s: 0.1\n"
                                       << common
                                       << "sources: [{name: raw, packet_channel: VELODYNE_PACKETS}]\n"
                                          "channels: {status: PACKETS_MAPPER_STATUS, delta: PACKETS_DELTA, "
                                          "request: PACKETS_REQUEST, query: PACKETS_QUERY, command: PACKETS_COMMAND}\n";
  auto packets = std::make_unique<Mapper>(
      std::vector<std::string>{kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "packets.yaml").string(),
                               "--in-memory", "--log-level", "info"},
      (dir_ / "packets.log").string(), url, "PACKETS_MAPPER_STATUS");
  ASSERT_TRUE(scans->reportsStatus(10s));
  ASSERT_TRUE(packets->reportsStatus(10s));
  ogf::testing::ChildProcess driver({kBin + "/ogf-driver", "--lcm-url", url, "--pcap", pcap->string(), "--speed", "1",
                                     "--status-channel", "DRIVER_TEST_STATUS"},
                                    (dir_ / "driver.log").string());
  ASSERT_TRUE(driver.wait(60s).has_value()) << driver.log();
  const auto same = [&](const Status& s) {
    const auto other = scans->latestStatus();
    return other && s.scans_mapped > 0 && s.scans_mapped == other->scans_mapped &&
           s.filter_checksum == other->filter_checksum;
  };
  // The scans mapper has every scan once the driver is done; the packets mapper its last one three scan
  // periods after the last packet.
  const auto done = packets->waitForStatus(same, 20s);
  const auto a = scans->latestStatus();
  ASSERT_TRUE(done && a) << "scans mapped from packets " << (packets->latestStatus() ? packets->latestStatus()->scans_mapped : -1)
                         << ", from scans " << (a ? a->scans_mapped : -1) << "\n" << packets->log();
  const auto* raw = sourceNamed(*done, "raw");
  ASSERT_TRUE(raw);
  EXPECT_TRUE(raw->packets);
  EXPECT_GT(raw->packets_in, 1000);
  EXPECT_EQ(raw->packets_rejected, 0);
  EXPECT_GE(done->scans_mapped, 48) << "the capture holds 50 revolutions";
  EXPECT_TRUE(scans->stop());
  EXPECT_TRUE(packets->stop());
}

}  // namespace
