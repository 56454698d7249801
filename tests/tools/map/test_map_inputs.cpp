// ogf-map's input parsers: odometry CSV (bad lines skipped and named by line), POSE messages of either
// type told apart by fingerprint, PCD (ascii and binary, VIEWPOINT), and the --config file (ogf-mapper's,
// values applied, keys the program does not use listed, errors named with file, line and key).
#include <gtest/gtest.h>

#include <bot_core/pose_t.hpp>
#include <ogf/odometry_t.hpp>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/pcd_file.hpp"
#include "ogf/map_io/pose_message.hpp"

namespace {

using namespace ogf;

template <class Message>
std::vector<std::uint8_t> encode(const Message& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_GE(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), 0);
  return bytes;
}

TEST(OdometryCsv, ReadsHeaderCommentsAndEveryWellFormedLine) {
  const auto odo = map_io::parseOdometryCsv(
      "utime,x,y,z,qw,qx,qy,qz\n# a comment\n100,1,2,3,1,0,0,0\n\n200, 1.5 ,2,3,0.7071068,0,0,0.7071068\n",
      "odo.csv");
  ASSERT_EQ(odo.poses.size(), 2u);
  EXPECT_EQ(odo.skipped, 0);
  EXPECT_EQ(odo.poses[1].utime, 200);
  EXPECT_DOUBLE_EQ(odo.poses[1].position.x(), 1.5);
  EXPECT_NEAR(odo.poses[1].orientation.z(), 0.7071068, 1e-12);
}

TEST(OdometryCsv, MalformedLinesAreSkippedAndNamedByFileAndLine) {
  const auto odo = map_io::parseOdometryCsv(
      "utime,x,y,z,qw,qx,qy,qz\n100,0,0,0,1,0,0,0\n200,0,0,0,1,0\n300,0,zero,0,1,0,0,0\n1e3,0,0,0,1,0,0,0\n"
      "400,0,0,0,1,0,0,0\n",
      "odo.csv");
  ASSERT_EQ(odo.poses.size(), 2u);
  EXPECT_EQ(odo.skipped, 3);
  ASSERT_EQ(odo.problems.size(), 3u);
  EXPECT_NE(odo.problems[0].find("odo.csv:3:"), std::string::npos) << odo.problems[0];
  EXPECT_NE(odo.problems[0].find("6 fields"), std::string::npos) << odo.problems[0];
  EXPECT_NE(odo.problems[1].find("odo.csv:4:"), std::string::npos) << odo.problems[1];
  EXPECT_NE(odo.problems[1].find("'zero'"), std::string::npos) << odo.problems[1];
  EXPECT_NE(odo.problems[2].find("odo.csv:5:"), std::string::npos) << odo.problems[2];
}

TEST(OdometryCsv, AnUnreadableFileIsAnErrorNamingIt) {
  const auto odo = map_io::readOdometryCsv("/nonexistent/odometry.csv");
  ASSERT_FALSE(odo.ok());
  EXPECT_NE(odo.error().message.find("/nonexistent/odometry.csv"), std::string::npos);
}

TEST(PoseMessage, OdometryAndBotCorePoseAreToldApartByFingerprint) {
  ogf::odometry_t o{};
  o.utime = 11;
  o.position[0] = 1.0;
  o.orientation[0] = 1.0;
  o.num_covariance = 0;
  bot_core::pose_t b{};
  b.utime = 22;
  b.pos[1] = 2.0;
  b.orientation[0] = 0.0;
  b.orientation[3] = 1.0;
  const auto po = map_io::decodePoseMessage(encode(o));
  const auto pb = map_io::decodePoseMessage(encode(b));
  ASSERT_TRUE(po.ok()) << po.error().message;
  ASSERT_TRUE(pb.ok()) << pb.error().message;
  EXPECT_EQ(po->utime, 11);
  EXPECT_DOUBLE_EQ(po->position.x(), 1.0);
  EXPECT_EQ(pb->utime, 22);
  EXPECT_DOUBLE_EQ(pb->position.y(), 2.0);
  EXPECT_DOUBLE_EQ(pb->orientation.z(), 1.0);
  auto other = encode(o);
  other[0] ^= 0xFF;
  EXPECT_FALSE(map_io::decodePoseMessage(other).ok());
}

TEST(Pcd, AsciiCloudWithViewpointGivesPointsAndRayOrigin) {
  const std::string pcd =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 4\n"
      "TYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 1 2 0.5 1 0 0 0\nPOINTS 3\nDATA ascii\n"
      "5 2 0.5 10\nnan nan nan 0\n5 2.2 0.7 12\n";
  const auto cloud = map_io::parsePcd(pcd, "a.pcd");
  ASSERT_TRUE(cloud.ok()) << cloud.error().message;
  ASSERT_EQ(cloud->points.size(), 2u);
  EXPECT_EQ(cloud->non_finite, 1);
  EXPECT_EQ(cloud->viewpoint_translation, Eigen::Vector3d(1, 2, 0.5));
  EXPECT_NEAR(cloud->points[1].y(), 2.2, 1e-12);
}

TEST(Pcd, BinaryCloudSkipsOtherFieldsByTheirSize) {
  std::string pcd =
      "VERSION 0.7\nFIELDS rgb x y z\nSIZE 4 4 4 8\nTYPE U F F F\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary\n";
  for (int i = 0; i < 2; ++i) {
    const std::uint32_t rgb = 0xFFFFFF;
    const float x = 1.0f + static_cast<float>(i), y = -2.0f;
    const double z = 0.25;
    char rec[20];
    std::memcpy(rec, &rgb, 4);
    std::memcpy(rec + 4, &x, 4);
    std::memcpy(rec + 8, &y, 4);
    std::memcpy(rec + 12, &z, 8);
    pcd.append(rec, sizeof rec);
  }
  const auto cloud = map_io::parsePcd(pcd, "b.pcd");
  ASSERT_TRUE(cloud.ok()) << cloud.error().message;
  ASSERT_EQ(cloud->points.size(), 2u);
  EXPECT_EQ(cloud->points[1], Eigen::Vector3d(2.0, -2.0, 0.25));
}

TEST(Pcd, TruncatedBinaryDataAndCompressedDataAreRefusedWithTheReason) {
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  const auto truncated = map_io::parsePcd(head + "DATA binary\n" + std::string(12, '\0'), "t.pcd");
  ASSERT_FALSE(truncated.ok());
  EXPECT_NE(truncated.error().message.find("t.pcd"), std::string::npos);
  const auto compressed = map_io::parsePcd(head + "DATA binary_compressed\n", "c.pcd");
  ASSERT_FALSE(compressed.ok());
  EXPECT_NE(compressed.error().message.find("binary_compressed"), std::string::npos);
}

// The offline programs read ogf-mapper's file: values land in the mapping configuration, the keys a
// program does not use are listed (not refused), and errors name the file, the line and the key.
TEST(OfflineConfigFile, ValuesApplyAndKeysTheProgramDoesNotUseAreListed) {
  const auto path = std::filesystem::temp_directory_path() / ("ogf-offline-config-" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "lcm_url: \"\"\nchannels: {scan: S}\ntime_base: host\nmap:\n  resolution: 0.1\n"
                         "  max_range: 12\n  extrinsic:\n    translation: [0, 0, 1.5]\n"
                         "filter:\n  threads: 2\n  clamp_z: 2.5\npose_correction: {mode: scan-match}\n";
  const auto read = map_io::readOfflineConfig(path, mapper_daemon::kUsedByEval);
  ASSERT_TRUE(read.ok()) << read.error().message;
  const pipeline::MapperConfig& c = read->options.map;
  EXPECT_DOUBLE_EQ(c.filter.resolution, 0.1);
  EXPECT_DOUBLE_EQ(c.fusion.measurement.resolution_m, 0.1);
  EXPECT_DOUBLE_EQ(c.fusion.measurement.max_range_m, 12.0);
  EXPECT_DOUBLE_EQ(c.fusion.extrinsic.translation_m.z(), 1.5);
  EXPECT_EQ(c.filter.threads, 2);
  EXPECT_DOUBLE_EQ(c.filter.clampZ, 2.5);
  EXPECT_TRUE(read->sets("time_base"));
  EXPECT_FALSE(read->sets("pose_source"));
  EXPECT_EQ(read->unused_keys, (std::vector<std::string>{"lcm_url", "channels.scan", "pose_correction.mode"}));
  EXPECT_NE(read->unusedNote("ogf-eval").find("ogf-eval does not use lcm_url, channels.scan, pose_correction.mode"),
            std::string::npos)
      << read->unusedNote("ogf-eval");
  const auto for_map = map_io::readOfflineConfig(path, mapper_daemon::kUsedByMap);
  ASSERT_TRUE(for_map.ok());
  EXPECT_EQ(for_map->unused_keys, (std::vector<std::string>{"lcm_url", "channels.scan"}));

  std::ofstream(path) << "map:\n  resolution: 0.2\nfilter:\n  treads: 2\n";
  const auto unknown = map_io::readOfflineConfig(path, mapper_daemon::kUsedByMap);
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find(path.string() + ":4: filter.treads"), std::string::npos)
      << unknown.error().message;
  std::ofstream(path) << "resolution: 0.2\n";
  const auto flat = map_io::readOfflineConfig(path, mapper_daemon::kUsedByMap);
  ASSERT_FALSE(flat.ok());
  EXPECT_NE(flat.error().message.find("use map.resolution"), std::string::npos) << flat.error().message;
  std::filesystem::remove(path);
}

}  // namespace

