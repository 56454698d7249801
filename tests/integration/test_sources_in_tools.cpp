// What the tools say about the mapper's sources, against a real ogf-mapper mapping two robots (one lidar
// each, each robot with its own odometry, 20 m apart) on udpm on loopback: `ogf-map-query sources` prints
// a line per source with its robot, sensor, channels and the counts and last position the mapper's own
// status holds, and --json the whole trail.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "support/multicast.hpp"
#include "support/test_directory.hpp"
#include "two_robots.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Status = ogf::mapper_status_t;
using Mapper = ogf::testing::DaemonProcess<Status>;

const std::string kBin = OGF_BIN_DIR;
constexpr int kSteps = 15;
constexpr double kApart = 20.0;  // metres along x between the robots

const ogf::source_status_t* sourceNamed(const Status& s, const std::string& name) {
  for (const auto& src : s.sources)
    if (src.name == name) return &src;
  return nullptr;
}

class SourcesInToolsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
    dir_ = ogf::testing::emptyTestDirectory("ogf-sources-in-tools");
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  // The mapper with robots r1 (sensor front) and r2 (sensor rear), fed kSteps scans each and waited for
  // until it mapped them all; its last status.
  std::optional<Status> mapTwoRobots(const std::string& url) {
    std::ofstream(dir_ / "mapper.yaml") << "status_interval_s: 0.1\n" << ogf::testing::kTwoRobotsSources;
    mapper_ = std::make_unique<Mapper>(
        std::vector<std::string>{kBin + "/ogf-mapper", "--lcm-url", url, "--config", (dir_ / "mapper.yaml").string(),
                                 "--in-memory", "--log-level", "info"},
        (dir_ / "mapper.log").string(), url, ogf::testing::kMapperStatusChannel);
    if (!mapper_->reportsStatus(10s)) return std::nullopt;
    lcm::LCM lcm(url);
    ogf::testing::feedTwoRobots(lcm, *mapper_, kSteps, kApart);
    return mapper_->waitForStatus([](const Status& s) { return s.scans_mapped == 2 * kSteps; }, 30s);
  }

  ogf::testing::Finished mapQuery(std::vector<std::string> args) {
    args.insert(args.begin(), kBin + "/ogf-map-query");
    return ogf::testing::runAndCapture(args, (dir_ / "map-query.log").string(), 30s);
  }

  fs::path dir_;
  std::unique_ptr<Mapper> mapper_;
};

std::string position(const ogf::source_status_t& s) {
  char text[64];
  const auto& p = s.trail.back();
  std::snprintf(text, sizeof text, "%.2f,%.2f,%.2f", static_cast<double>(p[0]), static_cast<double>(p[1]),
                static_cast<double>(p[2]));
  return text;
}

TEST_F(SourcesInToolsTest, MapQueryListsEachRobotsSensorWithTheMappersCountsAndPosition) {
  const std::string url = ogf::testing::loopbackUdpmUrl(105);
  const auto done = mapTwoRobots(url);
  ASSERT_TRUE(done) << mapper_->log();
  const auto* front = sourceNamed(*done, "front");
  const auto* rear = sourceNamed(*done, "rear");
  ASSERT_TRUE(front && rear);
  ASSERT_GT(front->trail_size, 1);
  ASSERT_GT(rear->trail_size, 1);

  const auto r = mapQuery({"--lcm-url", url, "--timeout", "10", "sources"});
  ASSERT_EQ(r.rc, 0) << r.output;
  EXPECT_NE(r.output.find("2 sources"), std::string::npos) << r.output;
  // robot sensor channel kind pose_channel inputs clocks scans_in mapped dropped rejected poses_in last trail
  for (const auto* s : {front, rear}) {
    const std::string line = "\n" + s->robot + " +" + s->name + " +" + s->scan_channel + " +scans +" + s->pose_channel +
                             " +ok +\\w+ +" + std::to_string(kSteps) + " +" + std::to_string(kSteps) + " +0 +0 +" +
                             std::to_string(s->poses_in) + " +" + position(*s) + " +" +
                             std::to_string(s->trail_size) + "\n";
    EXPECT_TRUE(std::regex_search(r.output, std::regex(line))) << "no line /" << line << "/ in\n" << r.output;
  }
  // r2's sensor is where r2's odometry put it, kApart further along x than r1's.
  EXPECT_NEAR(rear->trail.back()[0] - front->trail.back()[0], kApart, 1e-3);

  const auto j = mapQuery({"--lcm-url", url, "--timeout", "10", "sources", "--json"});
  ASSERT_EQ(j.rc, 0) << j.output;
  EXPECT_NE(j.output.find(R"({"robot":"r2","sensor":"rear","channel":"SCAN_R2","packets":false,)"
                          R"("pose_channel":"POSE_R2","inputs":"ok",)"),
            std::string::npos)
      << j.output;
  const auto rear_at = j.output.find(R"("sensor":"rear")");
  ASSERT_NE(rear_at, std::string::npos);
  const std::string rear_json = j.output.substr(rear_at);
  const auto trail_at = rear_json.find(R"("trail":[)");
  ASSERT_NE(trail_at, std::string::npos) << j.output;
  const std::string trail = rear_json.substr(trail_at, rear_json.find("]]", trail_at) - trail_at);
  EXPECT_EQ(std::count(trail.begin(), trail.end(), '['), 1 + rear->trail_size) << j.output;
  EXPECT_TRUE(mapper_->stop());
}

}  // namespace
