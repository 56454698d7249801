// A pause in the sensor stream: the real capture (a VLP-16 at 1200 rpm, no GPS) with an 11 s pause in the
// middle of a scan, replayed at 1x onto UDP by ogf-replay into ogf-driver, with odometry on the host clock
// into ogf-mapper, all real processes on udpm loopback. The scan the driver held when the stream stopped
// goes out with its own times, not 11 s late when packets resume: no scan is published stale (host time
// of publication against the scan's last packet), scans arrive in time order, and the mapper refuses none
// and maps every one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <thread>
#include <vector>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/device_clock_shift.hpp"
#include "support/host_odometry.hpp"
#include "support/message_counter.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

const std::string kBin = OGF_BIN_DIR;
constexpr std::int64_t kPauseUs = 11'000'000;

struct Arrival {
  std::int64_t received_utime;  // host clock, when the test's subscriber got it
  ogf::lidar_scan_t scan;
};

std::int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

TEST(SensorPause, TheScanHeldAtAPauseIsPublishedWithItsOwnTimeAndTheMapperRefusesNone) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-sensor-pause");
  // Data packet 1000 of 1902: mid-capture, inside a scan (about 37 packets a turn).
  const fs::path capture = dir / "paused.pcap";
  const auto error = ogf::testing::copyWithPause(pcap, capture, 1000, kPauseUs);
  ASSERT_FALSE(error.has_value()) << *error;
  std::ofstream(dir / "mapper.yaml") << "status_interval_s: 0.1\n";
  const std::string url = ogf::testing::loopbackUdpmUrl(250);
  const std::string data_port = std::to_string(40000 + (::getpid() % 20000) + 251);
  const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + 252);

  std::mutex mu;
  std::vector<Arrival> arrivals;
  ogf::testing::MessageCounter<ogf::lidar_scan_t> scans(url, "VELODYNE_SCAN", [&](const ogf::lidar_scan_t& s) {
    const std::lock_guard lk(mu);
    arrivals.push_back({wallUtime(), s});
  });
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config", (dir / "mapper.yaml").string()},
                (dir / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", data_port,
                 "--position-port", position_port},
                (dir / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(15s));
  ASSERT_TRUE(driver.reportsStatus(15s));
  std::int64_t published = 0;
  {
    ogf::testing::HostOdometry odometry(url);
    std::this_thread::sleep_for(200ms);
    ChildProcess replay({kBin + "/ogf-replay", "--pcap", capture.string(), "--dest", "127.0.0.1", "--data-port",
                         data_port, "--position-port", position_port, "--speed", "1"},
                        (dir / "replay.log").string());
    ASSERT_EQ(replay.wait(60s), 0) << replay.log();
    std::this_thread::sleep_for(500ms);
    ASSERT_TRUE(driver.stop());
    std::this_thread::sleep_for(300ms);
    const auto last = driver.latestStatus();
    ASSERT_TRUE(last.has_value());
    published = last->scans_published;
    ASSERT_GE(published, 50) << driver.log();
    const auto done =
        mapper.waitForStatus([&](const ogf::mapper_status_t& s) { return s.scans_mapped == published; }, 30s);
    const auto seen = mapper.latestStatus();
    ASSERT_TRUE(seen.has_value());
    EXPECT_TRUE(done.has_value()) << "mapped " << seen->scans_mapped << " of " << published << " scans, "
                                  << seen->scans_refused_time << " refused for their time\n" << mapper.log();
    EXPECT_EQ(seen->scans_refused_time, 0) << mapper.log();
  }
  EXPECT_TRUE(mapper.stop());

  const std::lock_guard lk(mu);
  ASSERT_EQ(static_cast<std::int64_t>(arrivals.size()), published);
  for (std::size_t i = 0; i < arrivals.size(); ++i) {
    const auto& a = arrivals[i];
    // Published promptly after its last packet: a scan's time plus the idle wait, never across the pause.
    EXPECT_LT(a.received_utime - a.scan.host_utime_end, kPauseUs / 2)
        << "scan " << a.scan.seq << " published " << static_cast<double>(a.received_utime - a.scan.host_utime_end) / 1e6
        << " s after its last packet\n" << driver.log();
    if (i > 0) {
      // In time order: no scan arrives after a newer one.
      EXPECT_GE(a.scan.host_utime_start, arrivals[i - 1].scan.host_utime_end) << "scan " << a.scan.seq;
      EXPECT_GT(a.scan.device_utime_start, arrivals[i - 1].scan.device_utime_start) << "scan " << a.scan.seq;
      EXPECT_EQ(a.scan.seq, arrivals[i - 1].scan.seq + 1);
    }
  }
  EXPECT_NE(driver.log().find("the sensor stream is idle"), std::string::npos) << driver.log();
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
