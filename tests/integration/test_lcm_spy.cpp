// scripts/lcm-spy.sh during the main job's pipeline: ogf-sim's lab world replayed at 1x onto UDP into
// ogf-driver, ogf-mapper mapping it with the simulated odometry. lcm-spy's receive path (Java LCM, lcm-spy's
// type lookup and decoding on the reader thread), run by the script's --text mode, sees every channel of
// both daemons at its true count and rate: the driver's scans as many as its status says it published, the
// packet batches, deltas and statuses as many as a C++ subscriber with a large buffer counted.
// Java LCM's own receive buffer (the kernel default) lets through about one scan in ten. Without a display
// the script (or, for a display it cannot open, its launcher) points to --text instead of a Java stack trace.
#include <gtest/gtest.h>
#include <unistd.h>

#include <ogf/driver_status_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include "support/file_text.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/message_counter.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Mapper = ogf::testing::DaemonProcess<ogf::mapper_status_t>;

const std::string kBin = OGF_BIN_DIR;
const std::string kScripts = OGF_SCRIPTS_DIR;
const std::string kJavaDir = OGF_JAVA_DIR;

bool onPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string d; std::getline(dirs, d, ':');) {
    if (!d.empty() && ::access((fs::path(d) / program).c_str(), X_OK) == 0) return true;
  }
  return false;
}

struct Seen {
  long long messages = 0;
  double hz = 0;
  long long undecodable = 0;
};

// The totals table the spy prints at exit: channel, type, messages, Hz, KB/s, undecodable.
std::map<std::string, Seen> totals(const std::string& log) {
  std::map<std::string, Seen> out;
  const auto at = log.rfind("totals over");
  if (at == std::string::npos) return out;
  std::istringstream lines(log.substr(at));
  const std::regex row(R"(^(\S+)\s+\S+\s+(\d+)\s+([0-9.]+)\s+[0-9.]+\s+(\d+)\s*$)");
  std::string title;
  std::getline(lines, title);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("at ", 0) == 0) break;  // a periodic table after the totals is not part of them
    std::smatch m;
    if (std::regex_match(line, m, row)) out[m[1]] = {std::stoll(m[2]), std::stod(m[3]), std::stoll(m[4])};
  }
  return out;
}

TEST(LcmSpy, SeesEveryChannelOfTheDaemonsAtItsTrueRate) {
  if (!onPath("java")) GTEST_SKIP() << "no java runtime (apt-get install default-jre): lcm-spy cannot run";
  if (!fs::exists(fs::path(kJavaDir) / "ogf_spy.jar") || !fs::exists(fs::path(kJavaDir) / "lcmtypes_ogf.jar"))
    GTEST_SKIP() << "ogf_spy.jar / lcmtypes_ogf.jar not built in " << kJavaDir << " (no JDK at configure time)";
  if (!fs::exists("/usr/share/java/lcm.jar")) GTEST_SKIP() << "liblcm-java is not installed";
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;

  const fs::path dir = ogf::testing::emptyTestDirectory("ogf-lcm-spy");
  const auto now_us = std::chrono::duration_cast<std::chrono::microseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
  {
    ChildProcess sim({kBin + "/ogf-sim", "--world", "lab", "--duration", "8", "--out", (dir / "sim").string(),
                      "--start-utime", std::to_string(now_us), "--log-level", "warn"},
                     (dir / "sim.log").string());
    ASSERT_EQ(sim.wait(120s), 0) << sim.log();
  }
  const std::string sim_yaml = ogf::testing::fileText(dir / "sim" / "sim.yaml");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(sim_yaml, m,
                                std::regex(R"(sensor_to_body: \{xyz: (\[[^\]]*\]), quaternion_wxyz: (\[[^\]]*\])\})")))
      << sim_yaml;
  std::ofstream(dir / "mapper.yaml") << "map:\n  extrinsic: {translation: " << m[1] << ", quaternion: " << m[2]
                                     << "}\n";

  // The daemons and the test's own subscribers on a large buffer; the spy on the URL a user would type.
  const std::string url = ogf::testing::loopbackUdpmUrl(240);
  const std::string spy_url = url.substr(0, url.find('?')) + "?ttl=0";
  const std::string data_port = std::to_string(40000 + (::getpid() % 20000) + 241);
  const std::string position_port = std::to_string(40000 + (::getpid() % 20000) + 242);
  ogf::testing::MessageCounter<ogf::velodyne_packets_t> packets(url, "VELODYNE_PACKETS");
  ogf::testing::MessageCounter<ogf::map_delta_t> deltas(url, "OGF_MAP_DELTA");
  ogf::testing::MessageCounter<ogf::mapper_status_t> mapper_statuses(url, "OGF_MAPPER_STATUS");

  ChildProcess spy({"/usr/bin/env", "OGF_JAVA_DIR=" + kJavaDir, "/bin/bash", kScripts + "/lcm-spy.sh", "--text",
                    "--lcm-url", spy_url},
                   (dir / "spy.log").string());
  for (int i = 0; i < 600 && spy.log().find("ogf-spy: listening") == std::string::npos; ++i)
    std::this_thread::sleep_for(50ms);
  ASSERT_NE(spy.log().find("ogf-spy: listening"), std::string::npos) << spy.log();

  Mapper mapper({kBin + "/ogf-mapper", "--lcm-url", url, "--state-dir", (dir / "state").string(), "--config",
                 (dir / "mapper.yaml").string(), "--log-level", "warn"},
                (dir / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
  Driver driver({kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port", data_port,
                 "--position-port", position_port, "--log-level", "warn"},
                (dir / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
  ASSERT_TRUE(driver.reportsStatus(15s));
  ASSERT_TRUE(mapper.reportsStatus(15s));
  {
    ChildProcess replay({kBin + "/ogf-replay", "--pcap", (dir / "sim" / "capture.pcap").string(), "--dest",
                         "127.0.0.1", "--data-port", data_port, "--position-port", position_port, "--speed", "1",
                         "--odometry", (dir / "sim" / "odometry.csv").string(), "--lcm-url", url},
                        (dir / "replay.log").string());
    ASSERT_EQ(replay.wait(60s), 0) << replay.log();
  }
  std::this_thread::sleep_for(300ms);
  ASSERT_TRUE(driver.stop());
  std::this_thread::sleep_for(300ms);
  const auto published = driver.latestStatus();
  ASSERT_TRUE(published.has_value());
  const std::int64_t scans = published->scans_published;
  ASSERT_TRUE(mapper.waitForStatus([&](const ogf::mapper_status_t& s) { return s.scans_in >= scans; }, 30s));
  std::this_thread::sleep_for(1500ms);  // the deltas of the last scan, and a status after it
  ASSERT_TRUE(mapper.stop(30s));
  std::this_thread::sleep_for(500ms);
  spy.signal(SIGTERM);  // the spy prints its totals and exits
  ASSERT_TRUE(spy.wait(20s).has_value()) << spy.log();

  const auto seen = totals(spy.log());
  const auto count = [&](const std::string& channel) {
    const auto it = seen.find(channel);
    return it == seen.end() ? 0LL : it->second.messages;
  };
  const std::string log = spy.log();
  EXPECT_EQ(log.find("\nat ", log.rfind("totals over")), std::string::npos) << "a table after the totals\n" << log;
  EXPECT_GE(scans, 70) << "an 8 s drive at 10 Hz";
  EXPECT_GE(count("VELODYNE_SCAN"), scans * 95 / 100) << log;
  EXPECT_LE(count("VELODYNE_SCAN"), scans) << log;
  EXPECT_GE(count("VELODYNE_PACKETS"), packets.count() * 95 / 100) << log;
  EXPECT_GE(count("VELODYNE_STATUS"), 5) << log;
  EXPECT_GT(deltas.count(), 0);
  EXPECT_GE(count("OGF_MAP_DELTA"), deltas.count() * 95 / 100) << log;
  EXPECT_GE(count("OGF_MAPPER_STATUS"), mapper_statuses.count() * 95 / 100) << log;
  // The rate between the first and the last scan the spy saw: 10 Hz played at 1x.
  if (seen.count("VELODYNE_SCAN")) {
    EXPECT_GT(seen.at("VELODYNE_SCAN").hz, 7.0) << log;
  }
  for (const auto& [channel, s] : seen) {
    if (channel == "LCM_SELF_TEST") continue;  // C LCM's own self-test message, no type
    EXPECT_EQ(s.undecodable, 0) << channel << "\n" << log;
  }
  std::cout << "[ figures ] published: scans " << scans << ", packet batches " << packets.count() << ", deltas "
            << deltas.count() << ", mapper statuses " << mapper_statuses.count() << "; lcm-spy saw: scans "
            << count("VELODYNE_SCAN") << ", packet batches " << count("VELODYNE_PACKETS") << ", deltas "
            << count("OGF_MAP_DELTA") << ", mapper statuses " << count("OGF_MAPPER_STATUS") << "\n";
  if (!HasFailure()) fs::remove_all(dir);
}

// Without a display the script says to use --text and exits 1, before Java prints a HeadlessException.
TEST(LcmSpyScript, WithoutADisplayItPointsToTextModeAndExitsOne) {
  const fs::path log = fs::temp_directory_path() / ("ogf-lcm-spy-nodisplay-" + std::to_string(::getpid()) + ".log");
  const auto r = ogf::testing::runAndCapture({"/usr/bin/env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY",
                                              "OGF_JAVA_DIR=" + kJavaDir, "/bin/bash", kScripts + "/lcm-spy.sh"},
                                             log.string(), 60s);
  fs::remove(log);
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_NE(r.output.find("no display to open lcm-spy's window on (DISPLAY and WAYLAND_DISPLAY are unset)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("lcm-spy.sh --text"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("Exception"), std::string::npos) << r.output;
}

// A display that is set but cannot be opened: the launcher gives the same advice instead of a stack trace.
TEST(LcmSpyScript, ADisplayThatCannotBeOpenedGetsTheSameAdvice) {
  if (!onPath("java")) GTEST_SKIP() << "no java runtime (apt-get install default-jre): lcm-spy cannot run";
  if (!fs::exists(fs::path(kJavaDir) / "ogf_spy.jar") || !fs::exists(fs::path(kJavaDir) / "lcmtypes_ogf.jar"))
    GTEST_SKIP() << "ogf_spy.jar / lcmtypes_ogf.jar not built in " << kJavaDir << " (no JDK at configure time)";
  if (!fs::exists("/usr/share/java/lcm.jar")) GTEST_SKIP() << "liblcm-java is not installed";
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(243);
  const fs::path log = fs::temp_directory_path() / ("ogf-lcm-spy-baddisplay-" + std::to_string(::getpid()) + ".log");
  // Display 97 on a host with no X server listening there (its socket would be /tmp/.X11-unix/X97).
  if (fs::exists("/tmp/.X11-unix/X97")) GTEST_SKIP() << "an X server answers on :97";
  const auto r = ogf::testing::runAndCapture({"/usr/bin/env", "-u", "WAYLAND_DISPLAY", "DISPLAY=:97",
                                              "OGF_JAVA_DIR=" + kJavaDir, "/bin/bash", kScripts + "/lcm-spy.sh",
                                              "--lcm-url", url},
                                             log.string(), 60s);
  fs::remove(log);
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_NE(r.output.find("ogf-spy: cannot open lcm-spy's window"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("lcm-spy.sh --text"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("\tat "), std::string::npos) << "a stack trace\n" << r.output;
}

}  // namespace
