// Test helper: writes what a ROS 2 recorder writes, so the reader is tested on bags whose contents are
// known: CDR messages (little or big endian) of the types ogf reads, and rosbag2 sqlite3 files with the
// same tables (schema, metadata, topics, messages) and a metadata.yaml listing them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "ogf/rosbag/ros_messages.hpp"

namespace ogf::testing {

class CdrWriter {
 public:
  explicit CdrWriter(bool big_endian = false);
  void u8(std::uint8_t v);
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void u32(std::uint32_t v);
  void f64(double v);
  void string(const std::string& v);
  void octets(std::span<const std::uint8_t> v);
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

 private:
  void align(std::size_t n);
  void put(std::uint64_t v, std::size_t size);
  std::vector<std::uint8_t> bytes_;
  bool big_endian_;
};

std::vector<std::uint8_t> encodeVelodyneScan(const rosbag::VelodyneScanMessage& m, bool big_endian = false);
std::vector<std::uint8_t> encodeOdometry(const rosbag::OdometryMessage& m, bool big_endian = false);
std::vector<std::uint8_t> encodeTfMessage(const rosbag::TfMessage& m, bool big_endian = false);

struct TestBagTopic {
  std::string name;
  std::string type;
};

struct TestBagMessage {
  std::string topic;
  std::int64_t timestamp_ns = 0;
  std::vector<std::uint8_t> data;
};

// Writes `dir`/bag_<i>.db3 for each group of messages (one file per element of `files`) and, when
// `with_metadata`, `dir`/metadata.yaml listing them; every file holds every topic.
void writeTestBag(const std::filesystem::path& dir, const std::vector<TestBagTopic>& topics,
                  const std::vector<std::vector<TestBagMessage>>& files, bool with_metadata = true);

struct CapturedPacket {
  std::int64_t utime;
  std::vector<std::uint8_t> payload;
};

// The first `n` data packets (to port 2368) of a real capture.
std::vector<CapturedPacket> capturedPackets(const std::filesystem::path& pcap, std::size_t n);

// The topics of writeSampleBag: /velodyne_packets, /odom, /tf and /imu/data (sensor_msgs/msg/Imu, not read).
extern const std::vector<TestBagTopic> kSampleTopics;

struct WrittenBag {
  std::vector<CapturedPacket> packets;
  std::vector<rosbag::OdometryMessage> odometry;
  std::vector<rosbag::TransformStampedMessage> base_link_tf;  // odom -> base_link, as written
};

// A bag of: `packets` in VelodyneScan messages of 38 stamped with their capture times, Odometry every 20 ms
// over the same time (values not round in binary, so "exactly" means every bit), TF with odom->base_link
// and base_link->velodyne at the same times plus a map->/base_link every 5th step, and 3 Imu messages.
// Split over two files when `split`; metadata.yaml unless `with_metadata` is false.
WrittenBag writeSampleBag(const std::filesystem::path& dir, const std::vector<CapturedPacket>& packets,
                          bool split, bool with_metadata = true);

}  // namespace ogf::testing
