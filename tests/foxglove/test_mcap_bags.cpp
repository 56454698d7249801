// ROS 2 bags in MCAP storage, written by the format's reference libraries (@mcap/core, with
// @foxglove/rosmsg2-serialization for the CDR messages), read by the programs as a user runs them: the real
// nebula VLP-16 bag rewritten as MCAP (uncompressed, zstd and lz4 chunks, indexed or not, as a file or a bag
// folder) decodes exactly as its sqlite3 original; a simulated drive recorded as an MCAP bag maps to the
// checksum of its pcap; a chunk damaged in the file is named by its offset while the rest is read.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "reference_scripts.hpp"
#include "support/shared_data.hpp"
#include "tools/map/map_summary.hpp"
#include "tools/map/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;
using ogf::testing::mapSummary;
using ogf::testing::runProgram;
using ogf::testing::runReferenceScript;

constexpr const char* kBag = "data/real/nebula_vlp16_dual/1673400471837873222";
constexpr const char* kDb3 = "data/real/nebula_vlp16_dual/1673400471837873222/1673400471837873222_0.db3";

long long totalOf(const std::string& stdout_text, const std::string& what) {
  std::smatch m;
  if (!std::regex_search(stdout_text, m, std::regex("total scans (\\d+) points (\\d+) packets (\\d+)")))
    return -1;
  return std::stoll(m[what == "scans" ? 1 : what == "points" ? 2 : 3]);
}

void writeMcap(const std::vector<std::string>& args, const ogf::testing::ScratchDir& dir) {
  const auto run = runReferenceScript("write_ros2_mcap.mjs", args, dir.path());
  ASSERT_EQ(run.exit_code, 0) << run.output;
}

class NebulaAsMcap : public ::testing::TestWithParam<std::vector<std::string>> {};

TEST_P(NebulaAsMcap, DecodesToTheSamePointsAndScansAsTheSqliteBag) {
  OGF_REQUIRE_REFERENCE_LIBRARIES();
  OGF_REQUIRE_SHARED_FILE(bag, kBag);
  OGF_REQUIRE_SHARED_FILE(db3, kDb3);
  ogf::testing::ScratchDir dir;
  const fs::path mcap = dir / "nebula.mcap";
  std::vector<std::string> args = {"--db3", db3.string(), "--out", mcap.string()};
  args.insert(args.end(), GetParam().begin(), GetParam().end());
  writeMcap(args, dir);
  const auto from_sqlite = runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string()}, dir.path());
  ASSERT_EQ(from_sqlite.exit_code, 0) << from_sqlite.output;
  const auto from_mcap = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.string()}, dir.path());
  ASSERT_EQ(from_mcap.exit_code, 0) << from_mcap.output;
  EXPECT_EQ(from_mcap.stdout_text, from_sqlite.stdout_text);
  EXPECT_EQ(totalOf(from_mcap.stdout_text, "points"), 59414) << from_mcap.stdout_text;
  EXPECT_EQ(totalOf(from_mcap.stdout_text, "packets"), 603) << from_mcap.stdout_text;
  // Point for point: the CSV of every point.
  const auto csv_sqlite =
      runProgram({OGF_DECODE_BINARY, "--rosbag2", bag.string(), "--quiet", "--csv", (dir / "a.csv").string()},
                 dir.path());
  const auto csv_mcap = runProgram(
      {OGF_DECODE_BINARY, "--rosbag2", mcap.string(), "--quiet", "--csv", (dir / "b.csv").string()},
      dir.path());
  ASSERT_EQ(csv_mcap.exit_code, 0) << csv_mcap.output;
  std::ifstream a(dir / "a.csv"), b(dir / "b.csv");
  const std::string ta((std::istreambuf_iterator<char>(a)), {}), tb((std::istreambuf_iterator<char>(b)), {});
  EXPECT_GT(ta.size(), 59414u);
  EXPECT_TRUE(ta == tb) << "the points of the MCAP bag differ from those of the sqlite3 bag";
}

INSTANTIATE_TEST_SUITE_P(Storage, NebulaAsMcap,
                         ::testing::Values(std::vector<std::string>{"--compression", "none"},
                                           std::vector<std::string>{"--compression", "zstd"},
                                           std::vector<std::string>{"--compression", "lz4"},
                                           std::vector<std::string>{"--compression", "zstd", "--no-index"},
                                           std::vector<std::string>{"--no-chunks", "--no-index"}));

TEST(McapBags, ABagFolderWithMetadataIsReadAsItsMcapFile) {
  OGF_REQUIRE_REFERENCE_LIBRARIES();
  OGF_REQUIRE_SHARED_FILE(db3, kDb3);
  ogf::testing::ScratchDir dir;
  fs::create_directories(dir / "rosbag2_2023_01_11");
  const fs::path mcap = dir / "rosbag2_2023_01_11" / "rosbag2_2023_01_11_0.mcap";
  writeMcap({"--db3", db3.string(), "--out", mcap.string(), "--compression", "zstd", "--metadata-yaml"}, dir);
  const auto direct = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.string()}, dir.path());
  ASSERT_EQ(direct.exit_code, 0) << direct.output;
  const auto folder = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.parent_path().string()}, dir.path());
  ASSERT_EQ(folder.exit_code, 0) << folder.output;
  EXPECT_EQ(folder.stdout_text, direct.stdout_text);
  // The folder above it, where `ros2 bag record` made the bag's folder.
  const auto above = runProgram({OGF_DECODE_BINARY, "--rosbag2", dir.path().string()}, dir.path());
  ASSERT_EQ(above.exit_code, 0) << above.output;
  EXPECT_EQ(above.stdout_text, direct.stdout_text);
}

TEST(McapBags, ASimulatedDriveRecordedAsAnMcapBagMapsToTheChecksumOfItsPcap) {
  OGF_REQUIRE_REFERENCE_LIBRARIES();
  ogf::testing::ScratchDir dir;
  ASSERT_EQ(runProgram({OGF_SIM_BINARY, "--out", (dir / "sim").string(), "--duration", "1.0"}, dir.path())
                .exit_code,
            0);
  const std::string pcap = (dir / "sim" / "capture.pcap").string();
  const std::string odometry = (dir / "sim" / "odometry.csv").string();
  fs::create_directories(dir / "bag");
  writeMcap({"--pcap", pcap, "--odometry", odometry, "--out", (dir / "bag" / "drive_0.mcap").string(),
             "--compression", "zstd", "--metadata-yaml"},
            dir);
  // A bag's stamps are receive (host) times: the pcap is mapped on the same clock.
  const auto from_pcap = runProgram({OGF_MAP_BINARY, "--pcap", pcap, "--odometry", odometry, "--time", "host",
                                     "--out", (dir / "a.map").string()},
                                    dir.path());
  ASSERT_EQ(from_pcap.exit_code, 0) << from_pcap.output;
  const auto from_bag = runProgram(
      {OGF_MAP_BINARY, "--rosbag2", (dir / "bag").string(), "--out", (dir / "b.map").string()}, dir.path());
  ASSERT_EQ(from_bag.exit_code, 0) << from_bag.output;
  ASSERT_FALSE(mapSummary(from_pcap.stdout_text).empty()) << from_pcap.output;
  EXPECT_EQ(mapSummary(from_bag.stdout_text), mapSummary(from_pcap.stdout_text)) << from_bag.output;
  EXPECT_NE(from_bag.output.find("poses of base_link in odom"), std::string::npos) << from_bag.output;
}

// The bytes of `file` with `at` changed (every bit flipped).
void flipByte(const fs::path& file, std::uint64_t at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(at));
  const int c = f.get();
  f.seekp(static_cast<std::streamoff>(at));
  f.put(static_cast<char>(c ^ 0xFF));
}

class DamagedChunk : public ::testing::TestWithParam<std::string> {};

TEST_P(DamagedChunk, IsNamedByItsOffsetAndTheOtherChunksAreDecoded) {
  OGF_REQUIRE_REFERENCE_LIBRARIES();
  OGF_REQUIRE_SHARED_FILE(db3, kDb3);
  ogf::testing::ScratchDir dir;
  const fs::path mcap = dir / "nebula.mcap";
  // One VelodyneScan message (about 150 packets) a chunk.
  writeMcap(
      {"--db3", db3.string(), "--out", mcap.string(), "--compression", GetParam(), "--chunk-size", "1000"},
      dir);
  const auto chunks = ogf::testing::referenceChunks(mcap, dir.path());
  ASSERT_EQ(chunks.size(), 4u);
  const auto whole = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.string(), "--quiet"}, dir.path());
  ASSERT_EQ(totalOf(whole.stdout_text, "packets"), 603) << whole.output;
  // A byte in the middle of the second chunk's records.
  flipByte(mcap, chunks[1].offset + chunks[1].length / 2);
  const auto damaged = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.string(), "--quiet"}, dir.path());
  EXPECT_EQ(damaged.exit_code, 0) << damaged.output;
  EXPECT_NE(damaged.output.find("chunk at byte " + std::to_string(chunks[1].offset)), std::string::npos)
      << damaged.output;
  const long long packets = totalOf(damaged.stdout_text, "packets");
  EXPECT_GT(packets, 400) << damaged.output;  // three of the four messages
  EXPECT_LT(packets, 603) << damaged.output;
}

INSTANTIATE_TEST_SUITE_P(Compression, DamagedChunk, ::testing::Values("none", "zstd", "lz4"));

TEST(McapBags, AFileCutInsideAChunkIsReadUpToTheCutAndSaysWhere) {
  OGF_REQUIRE_REFERENCE_LIBRARIES();
  OGF_REQUIRE_SHARED_FILE(db3, kDb3);
  ogf::testing::ScratchDir dir;
  const fs::path mcap = dir / "nebula.mcap";
  writeMcap({"--db3", db3.string(), "--out", mcap.string(), "--compression", "zstd", "--chunk-size", "1000"},
            dir);
  const auto chunks = ogf::testing::referenceChunks(mcap, dir.path());
  ASSERT_EQ(chunks.size(), 4u);
  fs::resize_file(mcap, chunks[2].offset + chunks[2].length / 2);
  const auto cut = runProgram({OGF_DECODE_BINARY, "--rosbag2", mcap.string(), "--quiet"}, dir.path());
  EXPECT_EQ(cut.exit_code, 0) << cut.output;
  EXPECT_NE(cut.output.find("record at byte " + std::to_string(chunks[2].offset)), std::string::npos)
      << cut.output;
  EXPECT_NE(cut.output.find("cut short"), std::string::npos) << cut.output;
  const long long packets = totalOf(cut.stdout_text, "packets");
  EXPECT_GT(packets, 250) << cut.output;  // the first two messages
  EXPECT_LT(packets, 603) << cut.output;
}

}  // namespace
