// scripts/record.sh as the README tells a user to record: it runs while ogf-driver decodes the real
// capture replayed at 1x onto UDP and the robot's odometry arrives, and its log holds every scan, packet
// batch and pose published; its own check says so.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/driver_status_t.hpp>

#include <csignal>
#include <filesystem>
#include <regex>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/host_odometry.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;

const std::string kBin = OGF_BIN_DIR;
const std::string kScripts = OGF_SCRIPTS_DIR;

// The message count of `channel` in record.sh's table, or -1.
long long recorded(const std::string& output, const std::string& channel) {
  std::smatch m;
  if (std::regex_search(output, m, std::regex("\n" + channel + " +([0-9]+) "))) return std::stoll(m[1]);
  return -1;
}

TEST(RecordScript, RecordingDuringAReplayHoldsEveryPublishedMessage) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-record");
  const std::string url = ogf::testing::loopbackUdpmUrl(230);
  const std::string data_port = std::to_string(40000 + (::getpid() % 20000) + 231);
  const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + 232);
  ChildProcess recorder({"/bin/bash", kScripts + "/record.sh", "--lcm-url", url, (dir / "drive.lcmlog").string()},
                        (dir / "record.log").string());
  for (int i = 0; i < 200 && !fs::exists(dir / "drive.lcmlog"); ++i) std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(fs::exists(dir / "drive.lcmlog")) << recorder.log();
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", data_port,
                 "--position-port", position_port, "--log-level", "warn"},
                (dir / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
  ASSERT_TRUE(driver.reportsStatus(15s));
  std::int64_t poses = 0;
  {
    ogf::testing::HostOdometry odometry(url);
    ChildProcess replay({kBin + "/ogf-replay", "--pcap", pcap.string(), "--dest", "127.0.0.1", "--data-port",
                         data_port, "--position-port", position_port, "--speed", "1"},
                        (dir / "replay.log").string());
    const auto rc = replay.wait(60s);
    ASSERT_EQ(rc, 0) << replay.log();
    std::this_thread::sleep_for(300ms);
    ASSERT_TRUE(driver.stop());
    std::this_thread::sleep_for(300ms);
    poses = odometry.published();
  }
  std::this_thread::sleep_for(500ms);
  const auto final_status = driver.latestStatus();
  ASSERT_TRUE(final_status.has_value());
  recorder.signal(SIGINT);
  const auto rc = recorder.wait(30s);
  const std::string out = recorder.log();
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("complete"), std::string::npos) << out;
  EXPECT_EQ(recorded(out, "VELODYNE_SCAN"), final_status->scans_published) << out;
  // A batch goes out with each scan that has packets of its own: one fewer than the scans here, as when the
  // driver writes straight to a log file.
  EXPECT_GE(recorded(out, "VELODYNE_PACKETS"), final_status->scans_published - 1) << out;
  EXPECT_EQ(recorded(out, "POSE"), poses) << out;
  EXPECT_GE(final_status->scans_published, 40);
  fs::remove_all(dir);
}

}  // namespace
