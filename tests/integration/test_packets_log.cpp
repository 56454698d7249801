// A log of the raw packets decodes again to the driver's scans: ogf-driver decodes the real capture and
// publishes scans and packet batches into an LCM log; ogf-map maps the log's scans and, told there are
// none, its packets, to the same map (checksum); ogf-decode decodes the packets as it decodes the capture;
// ogf-replay plays the packets onto UDP; scans missing from a log are reported with how many.
#include <gtest/gtest.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include <filesystem>
#include <regex>

#include "support/child_process.hpp"
#include "support/shared_data.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

const std::string kBin = OGF_BIN_DIR;

ogf::testing::Finished run(const std::vector<std::string>& args, const fs::path& log) {
  return ogf::testing::runAndCapture(args, log.string());
}

std::string match(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(pattern)) ? m[1].str() : std::string();
}

class PacketsLog : public ::testing::Test {
 protected:
  void SetUp() override {
    auto pcap = ogf::testing::sharedFile("data/real/vlp-16-test-90deg-1-50-frames.pcap");
    if (!pcap) GTEST_SKIP() << "shared data absent under " << ogf::testing::sharedDir();
    pcap_ = *pcap;
    dir_ = fs::temp_directory_path() / ("ogf-packets-log-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    log_ = dir_ / "drive.lcmlog";
    const auto d = run({kBin + "/ogf-driver", "--pcap", pcap_.string(), "--speed", "0", "--lcm-url",
                        "file://" + log_.string() + "?mode=w", "--log-level", "warn"},
                       dir_ / "driver.log");
    ASSERT_EQ(d.rc, 0) << d.output;
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  fs::path pcap_, dir_, log_;
};

TEST_F(PacketsLog, MapsToTheSameChecksumAsTheScans) {
  const auto scans = run({kBin + "/ogf-map", "--lcm-log", log_.string(), "--static", "--out",
                          (dir_ / "scans.ogfm").string()},
                         dir_ / "map-scans.log");
  ASSERT_EQ(scans.rc, 0) << scans.output;
  const auto packets = run({kBin + "/ogf-map", "--lcm-log", log_.string(), "--static", "--scan-channel", "NO_SCANS",
                            "--out", (dir_ / "packets.ogfm").string()},
                           dir_ / "map-packets.log");
  ASSERT_EQ(packets.rc, 0) << packets.output;
  EXPECT_NE(packets.output.find("decoded from the packets on VELODYNE_PACKETS"), std::string::npos) << packets.output;
  const std::string summary = R"(scans (\d+) measurements \d+ cells \d+ seconds [0-9.]+ checksum ([0-9a-f]+))";
  ASSERT_FALSE(match(scans.output, summary).empty()) << scans.output;
  EXPECT_GE(std::stoll(match(scans.output, summary)), 40);
  EXPECT_EQ(match(packets.output, summary), match(scans.output, summary));
  EXPECT_EQ(match(packets.output, R"(checksum ([0-9a-f]+))"), match(scans.output, R"(checksum ([0-9a-f]+))"))
      << scans.output << packets.output;
}

TEST_F(PacketsLog, DecodesLikeTheCapture) {
  const auto from_log = run({kBin + "/ogf-decode", "--lcm-log", log_.string(), "--quiet"}, dir_ / "decode-log.log");
  const auto from_pcap = run({kBin + "/ogf-decode", "--pcap", pcap_.string(), "--quiet"}, dir_ / "decode-pcap.log");
  ASSERT_EQ(from_log.rc, 0) << from_log.output;
  ASSERT_EQ(from_pcap.rc, 0) << from_pcap.output;
  const std::string totals = R"(total scans (\d+ points \d+ packets \d+ lost \d+))";
  ASSERT_FALSE(match(from_pcap.output, totals).empty()) << from_pcap.output;
  EXPECT_EQ(match(from_log.output, totals), match(from_pcap.output, totals)) << from_log.output;
}

TEST_F(PacketsLog, ReplaysOntoUdpAsTheCaptureDoes) {
  const std::string port = std::to_string(40000 + (::getpid() % 20000) + 235);
  const auto from_log = run({kBin + "/ogf-replay", "--lcm-log", log_.string(), "--fast", "--dest", "127.0.0.1",
                             "--data-port", port, "--position-port", port},
                            dir_ / "replay-log.log");
  const auto from_pcap = run({kBin + "/ogf-replay", "--pcap", pcap_.string(), "--fast", "--dest", "127.0.0.1",
                              "--data-port", port, "--position-port", port},
                             dir_ / "replay-pcap.log");
  ASSERT_EQ(from_log.rc, 0) << from_log.output;
  ASSERT_EQ(from_pcap.rc, 0) << from_pcap.output;
  const std::string counts = R"((data \d+ position \d+) other)";
  ASSERT_FALSE(match(from_pcap.output, counts).empty()) << from_pcap.output;
  EXPECT_EQ(match(from_log.output, counts), match(from_pcap.output, counts)) << from_log.output;
}

TEST_F(PacketsLog, MissingScansAreReportedWithTheirCount) {
  // The same log with scans 5..19 (in log order) left out.
  const fs::path gapped = dir_ / "gapped.lcmlog";
  {
    lcm::LogFile in(log_.string(), "r");
    lcm::LogFile out(gapped.string(), "w");
    ASSERT_TRUE(in.good() && out.good());
    int scan = 0;
    while (const lcm::LogEvent* e = in.readNextEvent()) {
      if (e->channel == "VELODYNE_SCAN" && scan++ >= 5 && scan <= 20) continue;
      lcm::LogEvent copy = *e;
      out.writeEvent(&copy);
    }
  }
  const auto r = run({kBin + "/ogf-map", "--lcm-log", gapped.string(), "--static", "--out", (dir_ / "g.ogfm").string()},
                     dir_ / "map-gapped.log");
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("VELODYNE_SCAN: 15 missing in 1 gap"), std::string::npos) << r.output;
}

}  // namespace
