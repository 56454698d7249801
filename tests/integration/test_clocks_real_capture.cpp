// The real capture (a VLP-16 without GPS), its device clock set 20 minutes ahead of the host's, replayed
// onto UDP into ogf-driver, with odometry stamped on the host clock, into two ogf-mappers as real
// processes on udpm loopback: one with the default configuration maps every scan on the host clock; one
// told time_base: device maps none and says why, once, in its log and its status.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/device_clock_shift.hpp"
#include "support/host_odometry.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using ogf::testing::HostOdometry;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

const std::string kBin = OGF_BIN_DIR;

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST(ClocksOnTheRealCapture, DefaultMapsEveryScanAndDeviceTimeBaseSaysWhyNone) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-clocks");
  std::ofstream(dir / "mapper.yaml") << "status_interval_s: 0.1\n";
  // Without a GPS lock the driver places each packet's counter in the host's hour, so the capture's own
  // counters would put its device clock anywhere within ±30 min of the host's depending on the time of
  // day. The counters are shifted so that the first packet reads 20 minutes past the host's time now.
  constexpr std::int64_t kAheadUs = 20LL * 60 * 1'000'000;
  const auto toh = ogf::testing::firstDataPacketToh(pcap);
  ASSERT_TRUE(toh.has_value()) << pcap;
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  const std::int64_t host_toh =
      std::chrono::duration_cast<std::chrono::microseconds>(now).count() % 3'600'000'000;
  const std::int64_t shift_us = host_toh + kAheadUs - static_cast<std::int64_t>(*toh);
  const fs::path capture = dir / "capture.pcap";
  const auto shift_error = ogf::testing::copyWithDeviceClockShift(pcap, capture, shift_us);
  ASSERT_FALSE(shift_error.has_value()) << *shift_error;
  const std::string url = ogf::testing::loopbackUdpmUrl(221);
  const std::string data_port = std::to_string(40000 + (::getpid() % 20000) + 222);
  const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + 223);

  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config", (dir / "mapper.yaml").string()},
                (dir / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
  Mapper device_mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config",
                        (dir / "mapper.yaml").string(), "--time-base", "device", "--status-channel",
                        "DEVICE_MAPPER_STATUS", "--delta-channel", "DEVICE_MAP_DELTA"},
                       (dir / "device-mapper.log").string(), url, "DEVICE_MAPPER_STATUS");
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", data_port,
                 "--position-port", position_port, "--log-level", "warn"},
                (dir / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
  ASSERT_TRUE(driver.started());
  ASSERT_TRUE(mapper.reportsStatus(15s));
  ASSERT_TRUE(device_mapper.reportsStatus(15s));
  {
    HostOdometry odometry(url);
    std::this_thread::sleep_for(200ms);
    ChildProcess replay({kBin + "/ogf-replay", "--pcap", capture.string(), "--dest", "127.0.0.1", "--data-port", data_port,
                         "--position-port", position_port, "--speed", "1"},
                        (dir / "replay.log").string());
    const auto rc = replay.wait(60s);
    ASSERT_TRUE(rc.has_value()) << replay.log();
    ASSERT_EQ(*rc, 0) << replay.log();
    std::this_thread::sleep_for(300ms);
    ASSERT_TRUE(driver.stop());
    std::this_thread::sleep_for(300ms);
    const auto ds = driver.latestStatus();
    ASSERT_TRUE(ds.has_value());
    ASSERT_GE(ds->scans_published, 40);
    const auto published = ds->scans_published;
    // The default mapper: every scan placed on the host clock.
    const auto done = mapper.waitForStatus(
        [&](const ogf::mapper_status_t& s) {
          return s.scans_in == published && s.scans_mapped + s.scans_dropped_no_pose + s.scans_dropped_behind +
                                                     s.scans_late + s.scans_rejected == published;
        },
        30s);
    ASSERT_TRUE(done.has_value()) << mapper.log();
    EXPECT_EQ(done->scans_mapped, published) << mapper.log();
    EXPECT_EQ(done->clocks, ogf::mapper_status_t::CLOCKS_AGREE);
    EXPECT_EQ(done->scan_clock, ogf::mapper_status_t::SCAN_CLOCK_HOST);
    EXPECT_LT(std::llabs(done->clock_offset_us), 1'000'000);
    // time_base: device: nothing can be placed, and the status and the log say so.
    // Scans wait for poses up to max_pose_wait_s; at this capture's 19 scans/s the 10-scan queue fills
    // first, so some leave it as "behind" rather than "no pose", and the time checks may refuse a device
    // time this far from the host's: none is mapped either way.
    const auto none = device_mapper.waitForStatus(
        [&](const ogf::mapper_status_t& s) {
          return s.scans_in == published &&
                 s.scans_dropped_no_pose + s.scans_dropped_behind + s.scans_refused_time == published;
        },
        30s);
    ASSERT_TRUE(none.has_value()) << device_mapper.log();
    EXPECT_EQ(none->scans_mapped, 0);
    EXPECT_EQ(none->clocks, ogf::mapper_status_t::CLOCKS_DISAGREE);
    EXPECT_EQ(none->scan_clock, ogf::mapper_status_t::SCAN_CLOCK_DEVICE);
    // 20 minutes less the time from the shift to the replay's start (the waits above: seconds).
    EXPECT_NEAR(static_cast<double>(std::llabs(none->clock_offset_us)), static_cast<double>(kAheadUs), 60e6);
  }
  EXPECT_TRUE(mapper.stop());
  EXPECT_TRUE(device_mapper.stop());
  const std::string log = device_mapper.log();
  EXPECT_EQ(countOf(log, "different clocks"), 1) << log;
  EXPECT_NE(log.find("set time_base: host"), std::string::npos) << log;
  EXPECT_EQ(countOf(mapper.log(), "different clocks"), 0) << mapper.log();
  fs::remove_all(dir);
}

}  // namespace
