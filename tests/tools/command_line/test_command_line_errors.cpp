// The programs as a user runs them, wrong: every error exits 2 (usage or configuration) or 1 (a runtime
// failure such as a missing input), names what is wrong as the user wrote it, and says it once.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using ogf::testing::ChildProcess;

const std::string kBin = OGF_BIN_DIR;

class CommandLineErrors : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ogf::testing::emptyTestDirectory("ogf-cli");
  }
  void TearDown() override { fs::remove_all(dir_); }

  ogf::testing::Finished run(const std::string& program, std::vector<std::string> args) {
    args.insert(args.begin(), kBin + "/" + program);
    return ogf::testing::runAndCapture(args, (dir_ / (program + ".log")).string(), 30s);
  }
  fs::path dir_;
};

int countOf(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

TEST_F(CommandLineErrors, NegativeResolutionSaysTheRuleNotARange) {
  for (const std::string program : {"ogf-map", "ogf-mapper"}) {
    const auto o = run(program, {"--resolution", "-1"});
    EXPECT_EQ(o.rc, 2) << program << ": " << o.output;
    EXPECT_NE(o.output.find("--resolution: must be greater than 0, got -1"), std::string::npos) << o.output;
    EXPECT_EQ(o.output.find("e+308"), std::string::npos) << o.output;
  }
}

TEST_F(CommandLineErrors, MistypedFlagIsNamedAsUnknown) {
  for (const std::string program : {"ogf-decode", "ogf-map", "ogf-replay", "ogf-driver", "ogf-mapper"}) {
    const auto o = run(program, {"--pcapp", "x.pcap"});
    EXPECT_EQ(o.rc, 2) << program << ": " << o.output;
    EXPECT_NE(o.output.find("unknown option --pcapp"), std::string::npos) << program << ": " << o.output;
    EXPECT_EQ(o.output.find("is required"), std::string::npos) << program << ": " << o.output;
  }
}

TEST_F(CommandLineErrors, MalformedValuesExitTwo) {
  EXPECT_EQ(run("ogf-decode", {}).rc, 2);                                   // no input
  EXPECT_EQ(run("ogf-mapper", {"--threads", "many"}).rc, 2);               // not a number
  EXPECT_EQ(run("ogf-replay", {"--pcap", "x", "--data-port", "70000"}).rc, 2);  // out of range
  EXPECT_EQ(run("ogf-driver", {"--source", "carrier-pigeon"}).rc, 2);       // not one of the choices
  EXPECT_EQ(run("ogf-map", {"--help"}).rc, 0);
}

TEST_F(CommandLineErrors, MissingLcmLogIsNamedByItsFlag) {
  const auto o = run("ogf-map", {"--lcm-log", "/nonexistent.lcmlog", "--out", (dir_ / "m.ogfm").string()});
  EXPECT_EQ(o.rc, 1) << o.output;
  EXPECT_NE(o.output.find("--lcm-log: /nonexistent.lcmlog: no such file"), std::string::npos) << o.output;
  EXPECT_EQ(o.output.find("odometry"), std::string::npos) << o.output;
}

TEST_F(CommandLineErrors, DecodeNamesAMissingCaptureOnce) {
  const auto o = run("ogf-decode", {"--pcap", "/nonexistent.pcap"});
  EXPECT_EQ(o.rc, 1) << o.output;
  EXPECT_EQ(countOf(o.output, "/nonexistent.pcap"), 1) << o.output;
}

TEST_F(CommandLineErrors, CutAngleOutOfRangeIsRefused) {
  for (const std::string program : {"ogf-decode", "ogf-driver"}) {
    const auto o = run(program, {"--pcap", "x.pcap", "--cut-angle", "400"});
    EXPECT_EQ(o.rc, 2) << program << ": " << o.output;
    EXPECT_NE(o.output.find("must be between -360 and 360, got 400"), std::string::npos) << o.output;
  }
}

TEST_F(CommandLineErrors, ConfigurationValuesNameFileLineAndKeyAsWritten) {
  const auto daemon_yaml = dir_ / "mapper.yaml";
  std::ofstream(daemon_yaml) << "time_base: host\nmap:\n  resolution: -0.1\n";
  auto o = run("ogf-mapper", {"--config", daemon_yaml.string()});
  EXPECT_EQ(o.rc, 2) << o.output;
  EXPECT_NE(o.output.find(daemon_yaml.string() + ":3: map.resolution: must be greater than 0, got -0.1"),
            std::string::npos)
      << o.output;
  // ogf-map reads the daemon's file the same way; a top-level key is refused naming the key to use.
  o = run("ogf-map", {"--config", daemon_yaml.string(), "--pcd", "x.pcd", "--out", (dir_ / "m").string()});
  EXPECT_EQ(o.rc, 2) << o.output;
  EXPECT_NE(o.output.find(daemon_yaml.string() + ":3: map.resolution"), std::string::npos) << o.output;
  const auto map_yaml = dir_ / "map.yaml";
  std::ofstream(map_yaml) << "map:\n  max_range: 30\nresolution: -1\n";
  o = run("ogf-map", {"--config", map_yaml.string(), "--pcd", "x.pcd", "--out", (dir_ / "m").string()});
  EXPECT_EQ(o.rc, 2) << o.output;
  EXPECT_NE(o.output.find(map_yaml.string() + ":3: resolution: not a key here: use map.resolution"), std::string::npos)
      << o.output;
}

// Needs the bus: the mapper starts, then is stopped.
TEST_F(CommandLineErrors, MapperWithoutStateDirectoryWarnsAtStart) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  ::unsetenv("STATE_DIRECTORY");
  const std::string url = ogf::testing::loopbackUdpmUrl(226);
  ogf::testing::DaemonProcess<ogf::mapper_status_t> mapper({kBin + "/ogf-mapper", "--lcm-url", url},
                                                           (dir_ / "mapper.log").string(), url,
                                                           ogf::testing::kMapperStatusChannel);
  for (int i = 0; i < 300 && mapper.log().find("mapping ") == std::string::npos; ++i) std::this_thread::sleep_for(50ms);
  EXPECT_TRUE(mapper.stop());
  EXPECT_NE(mapper.log().find("no state directory"), std::string::npos) << mapper.log();
  EXPECT_NE(mapper.log().find("in memory only"), std::string::npos) << mapper.log();
}

// The driver's log and its VELODYNE_STATUS give the same granted receive buffer.
TEST_F(CommandLineErrors, DriverLogAndStatusAgreeOnTheReceiveBuffer) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(227);
  // More than any rmem_max grants, so the driver says what it got.
  ogf::testing::DaemonProcess<ogf::driver_status_t> driver(
      {kBin + "/ogf-driver", "--lcm-url", url, "--bind-address", "127.0.0.1", "--data-port",
       std::to_string(40000 + (::getpid() % 20000) + 228), "--position-port",
       std::to_string(40000 + (::getpid() % 20000) + 229), "--receive-buffer", "1073741824"},
      (dir_ / "driver.log").string(), url, ogf::testing::kDriverStatusChannel);
  const auto s = driver.waitForStatus([](const auto& m) { return m.socket_receive_buffer > 0; }, 15s);
  EXPECT_TRUE(driver.stop());
  ASSERT_TRUE(s.has_value()) << driver.log();
  std::smatch m;
  const std::string log = driver.log();
  ASSERT_TRUE(std::regex_search(log, m, std::regex("granted a ([0-9]+) byte receive buffer"))) << log;
  EXPECT_EQ(std::stoll(m[1]), s->socket_receive_buffer) << log;
}

}  // namespace
