// --rosbag2 in the programs as a user runs them: ogf-decode prints for the real nebula bag exactly what it
// prints for the pcap derived from it, ogf-map makes the same map from both, a bag written here maps with
// its own Odometry or TF poses and names the topic it does not read, and missing bags or topics are
// errors that name them with the convention's exit codes.
#include <gtest/gtest.h>
#include <unistd.h>

#include <regex>
#include <string>
#include <vector>

#include "bag_writer.hpp"
#include "support/shared_data.hpp"
#include "tools/map/map_summary.hpp"
#include "tools/map/run_program.hpp"
#include "tools/map/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;
using ogf::testing::mapSummary;
using ogf::testing::runProgram;

constexpr const char* kBag = "data/real/nebula_vlp16_dual/1673400471837873222";
constexpr const char* kDerivedPcap = "data/real/derived/nebula_vlp16_dual_1673400471837873222.DERIVED.pcap";
constexpr const char* kCapture = "data/real/vlp-16-test-90deg-1-50-frames.pcap";

long long mappedScans(const std::string& stdout_text) {
  std::smatch m;
  return std::regex_search(stdout_text, m, std::regex(R"(^scans (\d+) )")) ? std::stoll(m[1]) : -1;
}

TEST(RosbagPrograms, OgfDecodeOfTheNebulaBagPrintsExactlyWhatItsDerivedPcapPrints) {
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  OGF_REQUIRE_SHARED_FILE(pcap, kDerivedPcap);
  ogf::testing::ScratchDir dir;
  const auto from_bag = runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string()}, dir.path());
  ASSERT_EQ(from_bag.exit_code, 0) << from_bag.output;
  const auto from_pcap = runProgram({OGF_DECODE_BINARY, "--pcap", pcap.string()}, dir.path());
  ASSERT_EQ(from_pcap.exit_code, 0) << from_pcap.output;
  EXPECT_EQ(from_bag.stdout_text, from_pcap.stdout_text);
  EXPECT_NE(from_bag.stdout_text.find(" packets 603 "), std::string::npos) << from_bag.stdout_text;
  EXPECT_NE(from_bag.stdout_text.find("model VLP-16 return_mode dual"), std::string::npos)
      << from_bag.stdout_text;
}

TEST(RosbagPrograms, OgfDecodeNamesAMissingBagOrTopicWithTheConventionsExitCodes) {
  ogf::testing::ScratchDir dir;
  const auto missing = runProgram({OGF_DECODE_BINARY, "--rosbag2", "/nonexistent/bag"}, dir.path());
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/bag: no such bag folder"), std::string::npos) << missing.output;
  const auto no_value = runProgram({OGF_DECODE_BINARY, "--rosbag2"}, dir.path());
  EXPECT_EQ(no_value.exit_code, 2) << no_value.output;
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  const auto topic =
      runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string(), "--packets-topic", "/points"}, dir.path());
  EXPECT_EQ(topic.exit_code, 2) << topic.output;
  EXPECT_NE(topic.output.find("no topic /points"), std::string::npos) << topic.output;
}

TEST(RosbagPrograms, OgfMapOfTheNebulaBagMakesTheMapOfItsDerivedPcap) {
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  OGF_REQUIRE_SHARED_FILE(pcap, kDerivedPcap);
  ogf::testing::ScratchDir dir;
  const auto from_bag =
      runProgram({OGF_MAP_BINARY, "--rosbag2", bag.string(), "--static", "--out", (dir / "bag.map").string()},
                 dir.path());
  ASSERT_EQ(from_bag.exit_code, 0) << from_bag.output;
  const auto from_pcap =
      runProgram({OGF_MAP_BINARY, "--pcap", pcap.string(), "--static", "--out", (dir / "pcap.map").string()},
                 dir.path());
  ASSERT_EQ(from_pcap.exit_code, 0) << from_pcap.output;
  ASSERT_FALSE(mapSummary(from_bag.stdout_text).empty()) << from_bag.stdout_text;
  EXPECT_EQ(mapSummary(from_bag.stdout_text), mapSummary(from_pcap.stdout_text));
}

TEST(RosbagPrograms, OgfMapUsesTheBagsOdometryOrTfAndListsTheTopicItDoesNotRead) {
  OGF_REQUIRE_SHARED_FILE(pcap, kCapture);
  ogf::testing::ScratchDir dir;
  const fs::path bag = dir / "bag";
  ogf::testing::writeSampleBag(bag, ogf::testing::capturedPackets(pcap, 200), false);
  const auto odometry =
      runProgram({OGF_MAP_BINARY, "--rosbag2", bag.string(), "--out", (dir / "a.map").string()}, dir.path());
  ASSERT_EQ(odometry.exit_code, 0) << odometry.output;
  EXPECT_NE(odometry.output.find(
                "not read (types ogf does not decode): /imu/data (sensor_msgs/msg/Imu, 3 messages)"),
            std::string::npos)
      << odometry.output;
  EXPECT_NE(odometry.output.find("poses of base_link in odom"), std::string::npos) << odometry.output;
  EXPECT_EQ(odometry.output.find("not covered"), std::string::npos) << odometry.output;
  // The scans the bag's packets decode to, every one of them mapped.
  const auto decoded = runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string(), "--quiet"}, dir.path());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(decoded.stdout_text, m, std::regex(R"(total scans (\d+) )")))
      << decoded.output;
  EXPECT_GE(std::stoll(m[1]), 4);
  EXPECT_EQ(mappedScans(odometry.stdout_text), std::stoll(m[1])) << odometry.output;

  const auto tf = runProgram(
      {OGF_MAP_BINARY, "--rosbag2", bag.string(), "--pose-topic", "/tf", "--out", (dir / "b.map").string()},
      dir.path());
  ASSERT_EQ(tf.exit_code, 0) << tf.output;
  EXPECT_EQ(mappedScans(tf.stdout_text), std::stoll(m[1])) << tf.output;
  EXPECT_NE(tf.output.find("base_link from map, not from odom"), std::string::npos) << tf.output;
}

TEST(RosbagPrograms, OgfMapWithoutPosesOrABagIsRefusedNamingWhy) {
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  ogf::testing::ScratchDir dir;
  const auto no_poses =
      runProgram({OGF_MAP_BINARY, "--rosbag2", bag.string(), "--out", (dir / "m").string()}, dir.path());
  EXPECT_EQ(no_poses.exit_code, 2) << no_poses.output;
  EXPECT_NE(no_poses.output.find("no nav_msgs/msg/Odometry topic and no /tf"), std::string::npos)
      << no_poses.output;
  const auto missing =
      runProgram({OGF_MAP_BINARY, "--rosbag2", "/nonexistent/bag", "--static", "--out", (dir / "m").string()},
                 dir.path());
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/bag: no such bag folder"), std::string::npos) << missing.output;
  EXPECT_FALSE(fs::exists(dir / "m"));
}

// The folder above a bag (where a recorder made the bag's own folder): both programs read the bag inside
// and say which, with the output the bag itself gives.
TEST(RosbagPrograms, TheFolderAboveTheNebulaBagIsReadAsTheBagInsideIt) {
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  ogf::testing::ScratchDir dir;
  const std::string note = bag.parent_path().string() + " holds no bag itself; reading the bag in its subfolder " +
                           bag.string();
  const auto above = runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.parent_path().string()}, dir.path());
  ASSERT_EQ(above.exit_code, 0) << above.output;
  EXPECT_NE(above.output.find(note), std::string::npos) << above.output;
  const auto direct = runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string()}, dir.path());
  EXPECT_EQ(above.stdout_text, direct.stdout_text);
  const auto mapped = runProgram({OGF_MAP_BINARY, "--rosbag2", bag.parent_path().string(), "--static", "--out",
                                  (dir / "m.map").string()},
                                 dir.path());
  ASSERT_EQ(mapped.exit_code, 0) << mapped.output;
  EXPECT_NE(mapped.output.find(note), std::string::npos) << mapped.output;
  EXPECT_GE(mappedScans(mapped.stdout_text), 1) << mapped.output;
}

}  // namespace
