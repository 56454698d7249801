// Bad input at ogf-mapper as a real process on real LCM (udpm on loopback): between two runs of valid
// scans and odometry, the scan and POSE channels receive messages with a wrong fingerprint, truncated
// ones, counts claiming 2^31 or 10^7 elements without the bytes, NaN and Inf coordinates and poses,
// non-unit quaternions, random bytes and a genuine scan above the configured pending-points limit.
// The map request channel and the navigation grid's request channel (OGF_NAV_REQUEST) get malformed requests
// too (wrong fingerprint, truncated, lying string lengths, random bytes). Checked: every one is counted
// (OGF_MAPPER_STATUS scans_rejected, poses_rejected, requests_rejected, nav_requests_rejected,
// scans_dropped_behind),
// the daemon keeps running, its peak RSS (VmHWM) does not grow by what the claims would have allocated,
// and the map after the bad input is exactly the map of the valid scans alone (same filter checksum as an
// offline ScanMapper fed only those).
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <bot_core/pose_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

#include "lcm_bytes.hpp"
#include "offline_checksum.hpp"
#include "support/process_memory.hpp"
#include "scan_feeder.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using ogf::testing::encodeMessage;
using ogf::testing::withCount;
using Bytes = std::vector<std::uint8_t>;

const std::string kBin = OGF_BIN_DIR;
constexpr int kPoints = 400;
// The mapper is configured to hold at most this many points waiting for odometry; one scan above it is a
// genuine (fully encoded) scan beyond the configured limit.
constexpr int kMaxPendingPoints = 20000;

// The malformed scans: each must be refused and counted in scans_rejected.
std::vector<Bytes> badScans(std::mt19937& rng) {
  const ogf::lidar_scan_t valid = ogf::testing::feedStep(3, kPoints).scan;  // an old scan: never mapped again
  const Bytes good = encodeMessage(valid);
  std::vector<Bytes> out;
  Bytes wrong_fp = good;
  wrong_fp[0] ^= 0x5A;
  out.push_back(wrong_fp);                                                              // wrong fingerprint
  out.push_back(encodeMessage(ogf::testing::feedStep(3, kPoints).poses.front()));      // another type
  out.push_back(Bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() / 2)));  // truncated
  out.push_back(Bytes(good.begin(), good.begin() + 20));                                // cut in the header
  out.push_back(Bytes(good.begin(), good.begin() + 3));                                 // cut in the fingerprint
  out.push_back(Bytes{});                                                               // empty
  Bytes trailing = good;
  trailing.push_back(0);
  out.push_back(trailing);  // trailing byte
  // Counts claiming what the bytes do not hold: the header of a scan with no points, its count patched.
  ogf::lidar_scan_t empty = valid;
  empty.num_points = 0;
  for (auto* v : {&empty.x, &empty.y, &empty.z, &empty.azimuth_deg}) v->clear();
  empty.intensity.clear();
  empty.ring.clear();
  empty.laser_id.clear();
  empty.return_type.clear();
  empty.time_offset_ns.clear();
  const Bytes header = encodeMessage(empty);
  for (std::int32_t claim : {std::numeric_limits<std::int32_t>::max(), 10'000'000, (1 << 20) + 1, 1000, -1,
                             std::numeric_limits<std::int32_t>::min()})
    out.push_back(withCount(header, claim));
  // Decodes, but is not a scan any sender makes.
  const auto patched = [&](auto edit) {
    ogf::lidar_scan_t s = valid;
    edit(s);
    return encodeMessage(s);
  };
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  out.push_back(patched([&](auto& s) { s.x[17] = nan; }));
  out.push_back(patched([&](auto& s) { s.y[0] = inf; }));
  out.push_back(patched([&](auto& s) { s.z[kPoints - 1] = -inf; }));
  out.push_back(patched([&](auto& s) { s.time_offset_ns[5] = -1; }));
  out.push_back(patched([&](auto& s) { s.device_utime_end = s.device_utime_start - 1; }));
  out.push_back(patched([&](auto& s) { s.host_utime_end = s.host_utime_start - 1; }));
  // Random bytes, random sizes (up to a whole fragmented LCM message).
  std::uniform_int_distribution<int> size(0, 70000), byte(0, 255);
  for (int i = 0; i < 40; ++i) {
    Bytes r(static_cast<std::size_t>(size(rng)));
    for (auto& b : r) b = static_cast<std::uint8_t>(byte(rng));
    out.push_back(r);
  }
  return out;
}

// The malformed POSE messages: each must be refused and counted in poses_rejected. Their times lie after
// every valid pose, so one wrongly accepted would make the valid odometry after it out of order.
std::vector<Bytes> badPoses(std::mt19937& rng) {
  ogf::odometry_t valid = ogf::testing::feedStep(4, kPoints).poses.back();
  valid.utime += 3'600'000'000LL;
  const Bytes good = encodeMessage(valid);
  std::vector<Bytes> out;
  Bytes wrong_fp = good;
  wrong_fp[7] ^= 0x01;
  out.push_back(wrong_fp);
  out.push_back(Bytes(good.begin(), good.end() - 1));
  out.push_back(Bytes(good.begin(), good.begin() + 9));
  out.push_back(Bytes{});
  Bytes trailing = good;
  trailing.push_back(0x7F);
  out.push_back(trailing);
  for (std::int32_t claim : {std::numeric_limits<std::int32_t>::max(), 10'000'000, 37, -5})
    out.push_back(withCount(good, claim));  // valid has no covariance: its count is the last field
  const auto patched = [&](auto edit) {
    ogf::odometry_t o = valid;
    edit(o);
    return encodeMessage(o);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  out.push_back(patched([&](auto& o) { o.position[0] = nan; }));
  out.push_back(patched([&](auto& o) { o.position[2] = -inf; }));
  out.push_back(patched([&](auto& o) { o.orientation[1] = inf; }));
  out.push_back(patched([&](auto& o) { o.orientation[0] = 2.0; }));  // |q| = 2
  out.push_back(patched([&](auto& o) {
    for (double& q : o.orientation) q = 0.0;  // no rotation at all
  }));
  // libbot2's pose_t on the same channel, equally checked.
  bot_core::pose_t bot{};
  bot.utime = valid.utime + 1;
  bot.orientation[0] = 1.0;
  bot.pos[1] = nan;
  out.push_back(encodeMessage(bot));
  bot.pos[1] = 0.0;
  bot.orientation[0] = 0.5;  // |q| = 0.5
  out.push_back(encodeMessage(bot));
  // A scan on the pose channel.
  out.push_back(encodeMessage(ogf::testing::feedStep(0, 10).scan));
  std::uniform_int_distribution<int> size(0, 2000), byte(0, 255);
  for (int i = 0; i < 40; ++i) {
    Bytes r(static_cast<std::size_t>(size(rng)));
    for (auto& b : r) b = static_cast<std::uint8_t>(byte(rng));
    out.push_back(r);
  }
  return out;
}

// Malformed keyframe requests: each must be refused and counted in requests_rejected.
std::vector<Bytes> badRequests(std::mt19937& rng) {
  ogf::map_request_t valid{};
  valid.utime = 1;
  valid.requester = "bad-input-test";
  valid.last_seq = 3;
  const Bytes good = encodeMessage(valid);
  std::vector<Bytes> out;
  Bytes wrong_fp = good;
  wrong_fp[0] ^= 0x80;
  out.push_back(wrong_fp);
  out.push_back(Bytes(good.begin(), good.end() - 1));
  out.push_back(Bytes(good.begin(), good.begin() + 5));
  out.push_back(Bytes{});
  // The requester's length (an int32 after the fingerprint and utime) lying in both directions.
  for (const std::int32_t lie : {std::numeric_limits<std::int32_t>::min(), -1, 0, 1 << 20,
                                 std::numeric_limits<std::int32_t>::max()})
    out.push_back(ogf::testing::withInt32At(good, 16, lie));
  std::uniform_int_distribution<int> size(0, 300), byte(0, 255);
  for (int i = 0; i < 10; ++i) {
    Bytes r(static_cast<std::size_t>(size(rng)));
    for (auto& b : r) b = static_cast<std::uint8_t>(byte(rng));
    out.push_back(r);
  }
  return out;
}

class MapperBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-badinput-mapper");
    // No periodic grid keyframe: the one after the bad requests answers the well-formed request.
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\nnav:\n  keyframe_interval_s: 1000\nfusion:\n"
                                        << "  max_pending_points: " << kMaxPendingPoints << "\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(MapperBadInput, MalformedScansAndPosesAreCountedAndRefusedAndTheMapIsThatOfTheValidScans) {
  const std::string url = ogf::testing::loopbackUdpmUrl(51);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config", (dir_ / "mapper.yaml").string(),
                 "--log-level", "warn"},
                (dir_ / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(15s));
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  const auto publishSteps = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      const auto step = ogf::testing::feedStep(i, kPoints);
      for (const auto& p : step.poses) lcm.publish("POSE", &p);
      lcm.publish("VELODYNE_SCAN", &step.scan);
      std::this_thread::sleep_for(20ms);
    }
  };

  publishSteps(0, 5);
  const auto before = mapper.waitForStatus([](const ogf::mapper_status_t& s) { return s.scans_mapped == 5; }, 30s);
  ASSERT_TRUE(before) << mapper.log();
  const auto hwm_before = ogf::testing::peakResidentKiB(mapper.process().pid());
  ASSERT_TRUE(hwm_before) << "cannot read /proc/" << mapper.process().pid() << "/status";

  std::mt19937 rng(20261121);
  const auto bad_scans = badScans(rng);
  const auto bad_poses = badPoses(rng);
  const auto bad_requests = badRequests(rng);
  for (const auto& m : bad_scans) {
    lcm.publish("VELODYNE_SCAN", m.data(), static_cast<unsigned int>(m.size()));
    std::this_thread::sleep_for(2ms);
  }
  for (const auto& m : bad_poses) {
    lcm.publish("POSE", m.data(), static_cast<unsigned int>(m.size()));
    std::this_thread::sleep_for(2ms);
  }
  for (const auto& m : bad_requests) {
    lcm.publish("OGF_MAP_REQUEST", m.data(), static_cast<unsigned int>(m.size()));
    lcm.publish("OGF_NAV_REQUEST", m.data(), static_cast<unsigned int>(m.size()));
    std::this_thread::sleep_for(2ms);
  }
  // A well-formed scan beyond the configured limit, timed between scans 4 and 5 so it is not late.
  ogf::lidar_scan_t big = ogf::testing::feedStep(4, kMaxPendingPoints + 1000).scan;
  big.utime += 1;
  big.device_utime_start += 1;
  big.host_utime_start += 1;
  lcm.publish("VELODYNE_SCAN", &big);
  const auto n_scans = static_cast<std::int64_t>(bad_scans.size());
  const auto n_poses = static_cast<std::int64_t>(bad_poses.size());
  const auto n_requests = static_cast<std::int64_t>(bad_requests.size());
  const auto counted = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) {
        return s.scans_rejected - before->scans_rejected == n_scans &&
               s.poses_rejected - before->poses_rejected == n_poses &&
               s.requests_rejected - before->requests_rejected == n_requests &&
               s.nav_requests_rejected - before->nav_requests_rejected == n_requests && s.scans_dropped_behind == 1;
      },
      30s);
  const auto last = mapper.latestStatus();
  ASSERT_TRUE(last);
  EXPECT_TRUE(counted) << "scans_rejected " << last->scans_rejected << " (sent " << n_scans << "), poses_rejected "
                       << last->poses_rejected << " (sent " << n_poses << "), requests_rejected "
                       << last->requests_rejected << " (sent " << n_requests << "), nav_requests_rejected "
                       << last->nav_requests_rejected << " (sent " << n_requests << "), scans_dropped_behind "
                       << last->scans_dropped_behind << "\n"
                       << mapper.log();
  EXPECT_TRUE(mapper.running()) << "the mapper exited:\n" << mapper.log();
  const auto hwm_after = ogf::testing::peakResidentKiB(mapper.process().pid());
  ASSERT_TRUE(hwm_after);
  // The claims alone would have allocated 24 bytes x 2^31 points; the genuine big scan is 0.5 MB. 64 MiB is
  // far above the noise of a growing map and far below any allocation for a claimed count.
  EXPECT_LT(*hwm_after - *hwm_before, 64 * 1024) << "VmHWM grew from " << *hwm_before << " to " << *hwm_after << " kB";

  publishSteps(5, 10);
  const auto after = mapper.waitForStatus([](const ogf::mapper_status_t& s) { return s.scans_mapped == 10; }, 30s);
  ASSERT_TRUE(after) << mapper.log();
  EXPECT_EQ(after->scans_in, 10 + n_scans + 1);
  EXPECT_EQ(after->scans_late, 0);
  EXPECT_EQ(after->scans_dropped_no_pose, 0);
  EXPECT_EQ(after->poses_in - after->poses_rejected, before->poses_in - before->poses_rejected + 50)
      << "every valid pose after the bad ones is accepted";
  EXPECT_EQ(static_cast<std::uint64_t>(after->filter_checksum), ogf::testing::offlineChecksum(10, kPoints))
      << "the bad input changed the map";
  EXPECT_EQ(after->requests_in, n_requests) << "only the malformed requests were sent";
  EXPECT_EQ(after->nav_requests_in, n_requests) << "only the malformed navigation grid requests were sent";
  // A well-formed request after the bad ones is still answered.
  ogf::map_request_t request{};
  request.requester = "bad-input-test";
  lcm.publish("OGF_MAP_REQUEST", &request);
  const auto answered = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) { return s.requests_in == n_requests + 1 && s.keyframes_sent > after->keyframes_sent; },
      30s);
  EXPECT_TRUE(answered) << mapper.log();
  lcm.publish("OGF_NAV_REQUEST", &request);
  const auto nav_answered = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) {
        return s.nav_requests_in == n_requests + 1 && s.nav_keyframes_sent > after->nav_keyframes_sent;
      },
      30s);
  EXPECT_TRUE(nav_answered) << mapper.log();
  std::printf("[ figures  ] mapper bad input: %lld malformed scans, %lld malformed poses and %lld malformed map "
              "(and as many navigation grid) requests counted, 1 scan of %d points dropped; VmHWM %lld kB before, %lld kB after; map checksum "
              "%016llx = reference\n",
              static_cast<long long>(n_scans), static_cast<long long>(n_poses), static_cast<long long>(n_requests),
              kMaxPendingPoints + 1000,
              static_cast<long long>(*hwm_before), static_cast<long long>(*hwm_after),
              static_cast<unsigned long long>(after->filter_checksum));
  EXPECT_TRUE(mapper.stop());
}

}  // namespace
