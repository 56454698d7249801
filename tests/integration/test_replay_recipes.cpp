// The README's replay recipes with real processes on udpm loopback and the real capture (a VLP-16 without
// GPS): ogf-replay with a fixed sensor's odometry (a static CSV on the capture's clock) stamps the poses on
// the clock ogf-driver gives the replayed packets, so ogf-mapper maps every scan; and a drive recorded with
// scripts/record.sh (lcm-logger) while the driver decodes the replayed capture replays, exactly as the
// README says (ogf-replay of the log's packets and poses into a driver and a mapper on a separate bus),
// into a mapper that maps every scan to the same filter checksum as ogf-map mapping the log offline.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/driver_status_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/device_clock_shift.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"
#include "support/static_odometry.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;
using ogf::testing::kDriverStatusChannel;
using ogf::testing::kMapperStatusChannel;

const std::string kBin = OGF_BIN_DIR;
const std::string kScripts = OGF_SCRIPTS_DIR;

std::string port(int slot) { return std::to_string(40000 + (::getpid() % 20000) + slot); }

std::string match(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(pattern)) ? m[1].str() : std::string();
}

class ReplayRecipes : public ::testing::Test {
 protected:
  void SetUp() override {
    auto pcap = ogf::testing::sharedFile("data/real/vlp-16-test-90deg-1-50-frames.pcap");
    if (!pcap) GTEST_SKIP() << "shared data absent under " << ogf::testing::sharedDir();
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    pcap_ = *pcap;
    dir_ = ogf::testing::emptyTestDirectory("ogf-replay-recipes");
    // A sensor on a tripod: the body at the origin from a second before the capture to a second after it,
    // on the capture's clock (2014).
    const auto span = ogf::testing::captureTimeSpan(pcap_);
    ASSERT_TRUE(span.has_value());
    capture_start_ = span->first;
    ASSERT_TRUE(ogf::testing::writeStaticOdometryCsv(dir_ / "static.csv", span->first - 1'000'000, span->second + 1'000'000));
    // The README's my-mapper.yaml, with a status every 0.1 s for the test.
    std::ofstream(dir_ / "my-mapper.yaml")
        << "time_base: auto\nstatus_interval_s: 0.1\nmap:\n"
           "  extrinsic: {translation: [0.2, 0.0, 0.8], rpy: [0.0, 0.0, 0.0]}\n";
  }
  void TearDown() override {
    if (!dir_.empty() && !HasFailure()) fs::remove_all(dir_);
  }

  fs::path pcap_, dir_;
  std::int64_t capture_start_ = 0;
};

TEST_F(ReplayRecipes, AFixedSensorsOdometryOnTheCaptureClockIsStampedOnTheDriversClockAndEveryScanIsMapped) {
  const std::string url = ogf::testing::loopbackUdpmUrl(260);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--in-memory", "--config", (dir_ / "my-mapper.yaml").string()},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", port(261),
                 "--position-port", port(262)},
                (dir_ / "driver.log").string(), url, kDriverStatusChannel);
  ASSERT_TRUE(mapper.reportsStatus(15s));
  ASSERT_TRUE(driver.reportsStatus(15s));
  const auto host_before = std::chrono::duration_cast<std::chrono::microseconds>(
                               std::chrono::system_clock::now().time_since_epoch())
                               .count();
  ChildProcess replay({kBin + "/ogf-replay", "--pcap", pcap_.string(), "--dest", "127.0.0.1", "--data-port", port(261),
                       "--position-port", port(262), "--odometry", (dir_ / "static.csv").string(), "--lcm-url", url},
                      (dir_ / "replay.log").string());
  ASSERT_EQ(replay.wait(60s), 0) << replay.log();
  std::this_thread::sleep_for(500ms);
  ASSERT_TRUE(driver.stop());
  std::this_thread::sleep_for(300ms);
  const auto published = driver.latestStatus();
  ASSERT_TRUE(published.has_value());
  ASSERT_GE(published->scans_published, 50);
  const auto done = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) { return s.scans_mapped == published->scans_published; }, 30s);
  const auto seen = mapper.latestStatus();
  EXPECT_TRUE(done.has_value()) << "mapped " << (seen ? seen->scans_mapped : -1) << " of "
                                << published->scans_published << "\n" << mapper.log() << replay.log();
  EXPECT_TRUE(mapper.stop());
  // The replay says which clock and by how much it moved the poses: the replay's start on the host clock
  // (a second after the first pose is due) minus the capture's start, about 12 years.
  const std::string log = replay.log();
  EXPECT_NE(log.find("odometry on the host clock (--odometry-clock auto: " + pcap_.string() +
                     " has no PPS-locked GPS time"),
            std::string::npos)
      << log;
  const std::string offset = match(log, R"(utime moves by \+([0-9.]+) s)");
  ASSERT_FALSE(offset.empty()) << log;
  EXPECT_NEAR(std::stod(offset), static_cast<double>(host_before - capture_start_) / 1e6 + 1.0, 30.0) << log;
}

TEST_F(ReplayRecipes, ARecordingReplaysAsTheReadmeSaysIntoAMapperOfEveryScanWithTheOfflineChecksum) {
  // Recording, as the README's step 4 says, the robot's bus while the driver decodes the sensor (here the
  // capture replayed onto UDP with the tripod's odometry).
  const std::string live = ogf::testing::loopbackUdpmUrl(263);
  const fs::path log = dir_ / "drive.lcmlog";
  ChildProcess recorder({"/bin/bash", kScripts + "/record.sh", "--lcm-url", live, "--channels",
                         "VELODYNE_PACKETS|VELODYNE_STATUS|POSE", log.string()},
                        (dir_ / "record.log").string());
  for (int i = 0; i < 200 && !fs::exists(log); ++i) std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(fs::exists(log)) << recorder.log();
  // The driver on the sensor's own ports, as on a robot, so the log holds them; on a loopback address of
  // this test's own (the most specific bind gets the datagrams), so another driver on them is no matter.
  const std::string sensor_lan = "127.0." + std::to_string(2 + ::getpid() % 250) + ".37";
  Driver live_driver({kBin + "/ogf-driver", "--lcm-url", live, "--bind-address", sensor_lan, "--log-level", "warn"},
                     (dir_ / "live-driver.log").string(), live, kDriverStatusChannel);
  ASSERT_TRUE(live_driver.reportsStatus(15s));
  {
    ChildProcess sensor({kBin + "/ogf-replay", "--pcap", pcap_.string(), "--dest", sensor_lan, "--odometry",
                         (dir_ / "static.csv").string(), "--lcm-url", live},
                        (dir_ / "sensor.log").string());
    ASSERT_EQ(sensor.wait(60s), 0) << sensor.log();
  }
  std::this_thread::sleep_for(500ms);
  ASSERT_TRUE(live_driver.stop());
  std::this_thread::sleep_for(1500ms);  // a last status into the log
  recorder.signal(SIGINT);
  ASSERT_EQ(recorder.wait(30s), 0) << recorder.log();
  EXPECT_NE(recorder.log().find("complete"), std::string::npos) << recorder.log();
  const auto recorded = live_driver.latestStatus();
  ASSERT_TRUE(recorded.has_value());
  ASSERT_GE(recorded->scans_published, 50);

  // The README's replay: a mapper and a driver on a separate bus, the log's packets and poses played into them.
  const std::string url = ogf::testing::loopbackUdpmUrl(266);
  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir_ / "replay-map").string(), "--config",
                 (dir_ / "my-mapper.yaml").string()},
                (dir_ / "mapper.log").string(), url, kMapperStatusChannel);
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", port(267),
                 "--position-port", port(268)},
                (dir_ / "driver.log").string(), url, kDriverStatusChannel);
  ChildProcess replay({kBin + "/ogf-replay", "--lcm-log", log.string(), "--odometry", log.string(), "--lcm-url", url,
                       "--data-port", port(267), "--position-port", port(268), "--start-delay", "2"},
                      (dir_ / "replay.log").string());
  ASSERT_EQ(replay.wait(60s), 0) << replay.log();
  std::this_thread::sleep_for(500ms);
  const auto replayed = driver.waitForStatus(
      [&](const ogf::driver_status_t& s) { return s.scans_published == recorded->scans_published; }, 10s);
  EXPECT_TRUE(replayed.has_value()) << "the replay's driver published " << driver.latestStatus()->scans_published
                                    << " scans, the recording's " << recorded->scans_published << "\n" << driver.log();
  const auto done = mapper.waitForStatus(
      [&](const ogf::mapper_status_t& s) { return s.scans_mapped == recorded->scans_published; }, 30s);
  const auto seen = mapper.latestStatus();
  ASSERT_TRUE(seen.has_value());
  EXPECT_TRUE(done.has_value()) << "mapped " << seen->scans_mapped << " of " << recorded->scans_published << "\n"
                                << mapper.log() << replay.log();
  EXPECT_TRUE(driver.stop());
  EXPECT_TRUE(mapper.stop(30s));

  // The same log offline, as the README says: the file's time_base (auto) places the packets on the host clock.
  const auto offline = ogf::testing::runAndCapture({kBin + "/ogf-map", "--lcm-log", log.string(), "--config",
                                                    (dir_ / "my-mapper.yaml").string(), "--out",
                                                    (dir_ / "drive.ogfm").string()},
                                                   (dir_ / "map.log").string());
  ASSERT_EQ(offline.rc, 0) << offline.output;
  EXPECT_EQ(match(offline.output, R"(scans (\d+) measurements)"), std::to_string(recorded->scans_published))
      << offline.output;
  const std::string checksum = match(offline.output, R"(checksum ([0-9a-f]+))");
  ASSERT_FALSE(checksum.empty()) << offline.output;
  EXPECT_EQ(std::stoull(checksum, nullptr, 16), static_cast<std::uint64_t>(seen->filter_checksum))
      << offline.output << mapper.log();
  std::cout << "[ figures ] log " << fs::file_size(log) << " bytes for " << recorded->scans_published
            << " scans; checksum " << checksum << "\n";
}

}  // namespace
