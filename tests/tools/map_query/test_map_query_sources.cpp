// ogf-map-query sources, run as a real process against a mapper status published on a real udpm bus on
// loopback: each source's line names its robot and sensor and carries its channels, state, counts, last
// position and trail length; --json carries the same and the whole trail; with no mapper on the bus it
// says so and exits 1. Skips, saying why, when udpm has no loopback route.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <ogf/mapper_status_t.hpp>

#include <atomic>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "support/child_process.hpp"
#include "support/multicast.hpp"
#include "support/source_status.hpp"

namespace {

namespace fs = std::filesystem;

ogf::source_status_t source(const std::string& robot, const std::string& name, int points) {
  std::vector<std::array<float, 3>> trail;
  for (int i = 0; i < points; ++i) trail.push_back({0.5f * static_cast<float>(i), 2.0f, 0.75f});
  auto s = ogf::testing::sourceStatus(robot, name, trail);
  s.clocks = ogf::mapper_status_t::CLOCKS_AGREE;
  s.scans_in = 50;
  s.scans_mapped = 45;
  s.scans_dropped_no_pose = 3;
  s.scans_late = 1;
  s.scans_rejected = 1;
  s.poses_in = 500;
  return s;
}

// Publishes `status` on OGF_MAPPER_STATUS every 100 ms while alive, as the mapper does at its own rate.
class StatusPublisher {
 public:
  StatusPublisher(const std::string& url, ogf::mapper_status_t status)
      : lcm_(url), status_(std::move(status)), thread_([this] {
          while (!stop_) {
            lcm_.publish("OGF_MAPPER_STATUS", &status_);
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
          }
        }) {}
  ~StatusPublisher() {
    stop_ = true;
    thread_.join();
  }

 private:
  lcm::LCM lcm_;
  ogf::mapper_status_t status_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

ogf::testing::Finished mapQuery(std::vector<std::string> args) {
  args.insert(args.begin(), std::string(OGF_BIN_DIR) + "/ogf-map-query");
  const std::string log = (fs::temp_directory_path() / ("ogf-map-query-sources-" + std::to_string(::getpid()))).string();
  auto finished = ogf::testing::runAndCapture(args, log, std::chrono::seconds(30));
  fs::remove(log);
  return finished;
}

ogf::mapper_status_t twoRobots() {
  ogf::mapper_status_t m{};
  m.utime = 1'700'000'000'000'000;
  m.sources = {source("r1", "front", 5), source("r2", "rear", 0)};
  m.num_sources = 2;
  return m;
}

TEST(MapQuerySources, EachSourceLineNamesItsRobotSensorStateCountsAndPosition) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(28);
  StatusPublisher mapper(bus, twoRobots());
  const auto r = mapQuery({"--lcm-url", bus, "--timeout", "10", "sources"});
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("2 sources"), std::string::npos) << r.output;
  // robot sensor channel kind pose_channel inputs clocks scans_in mapped dropped rejected poses_in last trail
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(\nr1 +front +VELODYNE_SCAN_front +scans +POSE_r1 +ok +agree +)"
                                                     R"(50 +45 +4 +1 +500 +2\.00,2\.00,0\.75 +5\n)")))
      << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(\nr2 +rear +VELODYNE_SCAN_rear +scans +POSE_r2 +ok +agree +)"
                                                     R"(50 +45 +4 +1 +500 +- +0\n)")))
      << r.output;
}

TEST(MapQuerySources, JsonCarriesEverySourceWithItsWholeTrail) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(29);
  StatusPublisher mapper(bus, twoRobots());
  const auto r = mapQuery({"--lcm-url", bus, "--timeout", "10", "sources", "--json"});
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find(R"({"robot":"r1","sensor":"front","channel":"VELODYNE_SCAN_front","packets":false,)"
                          R"("pose_channel":"POSE_r1","inputs":"ok","clocks":"agree","clock_offset_us":0,)"
                          R"("scans_in":50,"scans_mapped":45,"scans_dropped":4,"scans_rejected":1,)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(R"("trail":[[0.000,2.000,0.750],[0.500,2.000,0.750],[1.000,2.000,0.750],)"
                          R"([1.500,2.000,0.750],[2.000,2.000,0.750]]})"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find(R"({"robot":"r2","sensor":"rear",)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(R"("trail":[]}]})"), std::string::npos) << r.output;
}

TEST(MapQuerySources, WithoutAMapperItSaysSoAndExitsOne) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string bus = ogf::testing::loopbackUdpmUrl(30);
  const auto r = mapQuery({"--lcm-url", bus, "--timeout", "1", "sources"});
  EXPECT_EQ(r.rc, 1) << r.output;
  EXPECT_NE(r.output.find("no status on OGF_MAPPER_STATUS within 1.0 s"), std::string::npos) << r.output;
}

}  // namespace
