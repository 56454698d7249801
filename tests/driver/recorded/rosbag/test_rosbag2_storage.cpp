// ROS 2 bags written here with sqlite3, as a recorder writes them: the packets, Odometry and TF poses read
// back exactly, an unknown type is listed, split bags are read file by file, and a bag that is missing,
// damaged or of a kind not read gives an error naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <vector>

#include "bag_writer.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/map_io/bag_poses.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "ogf/rosbag/rosbag2_storage.hpp"
#include "support/shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace ogf::rosbag;
using ogf::map_io::choosePoseSource;
using ogf::map_io::readBagPoses;
using ogf::testing::CapturedPacket;
using ogf::testing::capturedPackets;
using ogf::testing::kSampleTopics;
using ogf::testing::writeSampleBag;
using ogf::testing::WrittenBag;

// A folder under the temp dir for one test, removed after it.
class Scratch {
 public:
  Scratch() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("ogf-rosbag-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

class WrittenBagTest : public ::testing::TestWithParam<bool> {};

TEST_P(WrittenBagTest, PacketsAndPosesReadBackExactlyAndTheUnknownTypeIsListed) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  Scratch scratch;
  const bool split = GetParam();
  const WrittenBag w = writeSampleBag(scratch.path(), capturedPackets(pcap, 200), split);
  ASSERT_EQ(w.packets.size(), 200U);
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_TRUE(bag) << bag.error().message;
  EXPECT_EQ(bag->files().size(), split ? 2U : 1U);
  ASSERT_EQ(bag->topics().size(), 4U);
  EXPECT_EQ(bag->topic("/velodyne_packets")->message_count, 6);  // 200 packets in messages of 38
  EXPECT_EQ(bag->topic("/odom")->message_count, static_cast<std::int64_t>(w.odometry.size()));
  EXPECT_EQ(undecodedTopicsSummary(bag->topics()), "/imu/data (sensor_msgs/msg/Imu, 3 messages)");

  auto topic = choosePacketTopic(*bag, "");
  ASSERT_TRUE(topic && *topic);
  EXPECT_EQ(**topic, "/velodyne_packets");
  std::vector<CapturedPacket> read;
  auto counts = readBagPackets(*bag, **topic, [&](const BagPacket& p) {
    read.push_back({p.host_utime, {p.payload.begin(), p.payload.end()}});
  });
  ASSERT_TRUE(counts) << counts.error().message;
  EXPECT_EQ(counts->messages, 6);
  EXPECT_EQ(counts->skipped, 0);
  ASSERT_EQ(read.size(), w.packets.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].utime, w.packets[i].utime) << "packet " << i;
    EXPECT_EQ(read[i].payload, w.packets[i].payload) << "packet " << i;
  }

  // Odometry: the default source, every pose exactly as written.
  auto source = choosePoseSource(*bag, "");
  ASSERT_TRUE(source && *source);
  EXPECT_EQ((*source)->topic, "/odom");
  auto odo = readBagPoses(*bag, **source);
  ASSERT_TRUE(odo) << odo.error().message;
  EXPECT_EQ(odo->parent_frame, "odom");
  EXPECT_EQ(odo->child_frame, "base_link");
  ASSERT_EQ(odo->poses.size(), w.odometry.size());
  for (std::size_t i = 0; i < w.odometry.size(); ++i) {
    const auto& p = odo->poses[i];
    const auto& m = w.odometry[i];
    EXPECT_EQ(p.utime, m.header.stamp.utime());
    EXPECT_EQ(p.position.x(), m.position.x);
    EXPECT_EQ(p.position.y(), m.position.y);
    EXPECT_EQ(p.position.z(), m.position.z);
    EXPECT_EQ(p.orientation.w(), m.orientation.w);
    EXPECT_EQ(p.orientation.z(), m.orientation.z);
    EXPECT_EQ(p.orientation.x(), 0.0);
  }

  // TF: base_link from odom only; the map->base_link transforms are skipped and said so.
  auto tf_source = choosePoseSource(*bag, "/tf");
  ASSERT_TRUE(tf_source && *tf_source);
  auto tf = readBagPoses(*bag, **tf_source);
  ASSERT_TRUE(tf) << tf.error().message;
  EXPECT_EQ(tf->parent_frame, "odom");
  ASSERT_EQ(tf->poses.size(), w.base_link_tf.size());
  for (std::size_t i = 0; i < tf->poses.size(); ++i) {
    EXPECT_EQ(tf->poses[i].utime, w.base_link_tf[i].header.stamp.utime());
    EXPECT_EQ(tf->poses[i].position.x(), w.base_link_tf[i].translation.x);
  }
  EXPECT_EQ(tf->skipped, static_cast<std::int64_t>((w.base_link_tf.size() + 4) / 5));
  ASSERT_FALSE(tf->problems.empty());
  EXPECT_NE(tf->problems.front().find("from map, not from odom"), std::string::npos) << tf->problems.front();
}

INSTANTIATE_TEST_SUITE_P(OneFileOrSplit, WrittenBagTest, ::testing::Bool());

TEST(Rosbag2Storage, WithoutMetadataEveryDb3IsReadAndOneDb3FileAlone) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  Scratch scratch;
  writeSampleBag(scratch.path(), capturedPackets(pcap, 76), true, false);
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_TRUE(bag) << bag.error().message;
  EXPECT_EQ(bag->files().size(), 2U);
  EXPECT_EQ(bag->topic("/velodyne_packets")->message_count, 2);
  auto one = Rosbag2Storage::open(scratch.path() / "bag_0.db3");
  ASSERT_TRUE(one) << one.error().message;
  EXPECT_EQ(one->files().size(), 1U);
}

TEST(Rosbag2Storage, TopicChoicesAreRefusedWithTheirReason) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  Scratch scratch;
  writeSampleBag(scratch.path(), capturedPackets(pcap, 10), false);
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_TRUE(bag) << bag.error().message;
  auto not_there = choosePacketTopic(*bag, "/points");
  ASSERT_FALSE(not_there);
  EXPECT_NE(not_there.error().message.find("no topic /points"), std::string::npos);
  auto wrong_type = choosePacketTopic(*bag, "/odom");
  ASSERT_FALSE(wrong_type);
  EXPECT_NE(wrong_type.error().message.find("nav_msgs/msg/Odometry, not velodyne_msgs/msg/VelodyneScan"),
            std::string::npos)
      << wrong_type.error().message;
  EXPECT_FALSE(choosePoseSource(*bag, "/imu/data"));
}

TEST(Rosbag2Storage, AMissingFolderIsNamed) {
  auto bag = Rosbag2Storage::open("/nonexistent/bag");
  ASSERT_FALSE(bag);
  EXPECT_EQ(bag.error().message, "/nonexistent/bag: no such bag folder");
}

TEST(Rosbag2Storage, AFileListedInMetadataButMissingIsNamed) {
  Scratch scratch;
  ogf::testing::writeTestBag(scratch.path(), kSampleTopics, {{}});
  fs::remove(scratch.path() / "bag_0.db3");
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(bag);
  EXPECT_NE(bag.error().message.find((scratch.path() / "bag_0.db3").string() +
                                     ": listed in metadata.yaml but missing"),
            std::string::npos)
      << bag.error().message;
}

TEST(Rosbag2Storage, ADamagedDatabaseIsNamed) {
  Scratch scratch;
  ogf::testing::writeTestBag(scratch.path(), kSampleTopics, {{}});
  const fs::path db = scratch.path() / "bag_0.db3";
  std::ofstream(db, std::ios::binary | std::ios::trunc)
      << "this is not an sqlite database, it is a text file";
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(bag);
  EXPECT_EQ(bag.error().message.rfind(db.string() + ": ", 0), 0U) << bag.error().message;
}

TEST(Rosbag2Storage, ATruncatedDatabaseIsAnErrorNamingItNotACrash) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  Scratch scratch;
  writeSampleBag(scratch.path(), capturedPackets(pcap, 400), false);
  const fs::path db = scratch.path() / "bag_0.db3";
  const auto full = fs::file_size(db);
  for (const auto keep : {full / 2, full / 5, std::uintmax_t{100}}) {
    fs::resize_file(db, keep);
    auto bag = Rosbag2Storage::open(scratch.path());
    std::string error = bag ? "" : bag.error().message;
    if (bag) {
      auto read = readBagPackets(*bag, "/velodyne_packets", [](const BagPacket&) {});
      if (!read) error = read.error().message;
    }
    ASSERT_FALSE(error.empty()) << "a database cut to " << keep << " of " << full
                                << " bytes read without error";
    EXPECT_EQ(error.rfind(db.string() + ": ", 0), 0U) << error;
  }
}

TEST(Rosbag2Storage, DamagedMetadataIsNamedWithItsLine) {
  Scratch scratch;
  ogf::testing::writeTestBag(scratch.path(), kSampleTopics, {{}});
  std::ofstream(scratch.path() / "metadata.yaml", std::ios::trunc)
      << "rosbag2_bagfile_information:\n  version: 5\n  relative_file_paths: [bag_0.db3\n";
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(bag);
  EXPECT_EQ(bag.error().message.rfind((scratch.path() / "metadata.yaml").string() + ":", 0), 0U)
      << bag.error().message;
}

TEST(Rosbag2Storage, CompressedBagsAndOtherStoragePluginsAreRefusedByName) {
  Scratch scratch;
  std::ofstream(scratch.path() / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  storage_identifier: foo\n  relative_file_paths: [x.foo]\n";
  auto other = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(other);
  EXPECT_NE(other.error().message.find("'foo': only sqlite3 and mcap bags are read"), std::string::npos)
      << other.error().message;
  // An MCAP bag whose file is missing is named as such, not refused for its storage.
  std::ofstream(scratch.path() / "metadata.yaml", std::ios::trunc)
      << "rosbag2_bagfile_information:\n  storage_identifier: mcap\n  relative_file_paths: [x.mcap]\n";
  auto mcap = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(mcap);
  EXPECT_NE(mcap.error().message.find("x.mcap: listed in metadata.yaml but missing"), std::string::npos)
      << mcap.error().message;
  std::ofstream(scratch.path() / "metadata.yaml", std::ios::trunc)
      << "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n  compression_format: zstd\n"
         "  relative_file_paths: [x.db3.zstd]\n";
  auto zstd = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(zstd);
  EXPECT_NE(zstd.error().message.find("compressed bag (zstd)"), std::string::npos) << zstd.error().message;
}

TEST(Rosbag2Storage, AMessageThatDoesNotDecodeIsSkippedAndDescribed) {
  Scratch scratch;
  ogf::testing::writeTestBag(scratch.path(), kSampleTopics,
                             {{{"/velodyne_packets", 1000, {0x00, 0x01, 0x00, 0x00, 0x05, 0x00}}}});
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_TRUE(bag) << bag.error().message;
  auto counts =
      readBagPackets(*bag, "/velodyne_packets", [](const BagPacket&) { FAIL() << "no packet expected"; });
  ASSERT_TRUE(counts) << counts.error().message;
  EXPECT_EQ(counts->skipped, 1);
  ASSERT_EQ(counts->problems.size(), 1U);
  EXPECT_NE(counts->problems[0].find(
                "bag_0.db3: message 1 on /velodyne_packets: velodyne_msgs/msg/VelodyneScan: byte 4"),
            std::string::npos)
      << counts->problems[0];
}

}  // namespace

TEST(Rosbag2Storage, TheFolderAboveOneBagOpensThatBagAndSaysSo) {
  Scratch scratch;
  const fs::path inner = scratch.path() / "rosbag2_2024_01_01-12_00_00";
  ogf::testing::writeTestBag(inner, kSampleTopics, {{{"/odom", 1000, {0x00, 0x01, 0x00, 0x00}}}});
  fs::create_directories(scratch.path() / "notes");  // a folder that is no bag does not count
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_TRUE(bag) << bag.error().message;
  EXPECT_EQ(bag->path(), inner);
  EXPECT_EQ(bag->searchedFolder(), scratch.path());
  ASSERT_EQ(bag->files().size(), 1U);
  EXPECT_EQ(bag->topic("/odom")->message_count, 1);
  EXPECT_EQ(bag->whereFound(), scratch.path().string() + " holds no bag itself; reading the bag in its subfolder " +
                                   inner.string());
  // Given the bag itself, nothing was searched.
  auto direct = Rosbag2Storage::open(inner);
  ASSERT_TRUE(direct) << direct.error().message;
  EXPECT_TRUE(direct->searchedFolder().empty());
  EXPECT_TRUE(direct->whereFound().empty());
}

TEST(Rosbag2Storage, TheFolderAboveSeveralBagsIsRefusedWithTheirNames) {
  Scratch scratch;
  ogf::testing::writeTestBag(scratch.path() / "run_b", kSampleTopics, {{}});
  ogf::testing::writeTestBag(scratch.path() / "run_a", kSampleTopics, {{}}, /*with_metadata=*/false);
  auto bag = Rosbag2Storage::open(scratch.path());
  ASSERT_FALSE(bag);
  EXPECT_EQ(bag.error().message,
            scratch.path().string() +
                ": no metadata.yaml and no .db3 or .mcap file; 2 subfolders hold bags (run_a, "
                "run_b): give one of them");
  fs::create_directories(scratch.path() / "empty");
  auto none = Rosbag2Storage::open(scratch.path() / "empty");
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().message.find("no subfolder holding one"), std::string::npos) << none.error().message;
}

TEST(Rosbag2Storage, TheRealNebulaBagOpensFromTheFolderAboveIt) {
  OGF_REQUIRE_SHARED_FILE(bag_dir, "data/real/nebula_vlp16_dual/1673400471837873222");
  auto bag = Rosbag2Storage::open(bag_dir.parent_path());
  ASSERT_TRUE(bag) << bag.error().message;
  EXPECT_EQ(bag->path(), bag_dir);
  ASSERT_FALSE(bag->topicsOfType(kVelodyneScanType).empty());
}
