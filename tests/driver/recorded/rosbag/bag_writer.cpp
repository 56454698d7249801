#include "bag_writer.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <fstream>

#include "ogf/driver_sources/pcap_file_reader.hpp"

namespace ogf::testing {

CdrWriter::CdrWriter(bool big_endian)
    : bytes_{0x00, static_cast<std::uint8_t>(big_endian ? 0x00 : 0x01), 0, 0}, big_endian_(big_endian) {}

void CdrWriter::align(std::size_t n) {
  while ((bytes_.size() - 4) % n != 0) bytes_.push_back(0);
}

void CdrWriter::put(std::uint64_t v, std::size_t size) {
  align(size);
  for (std::size_t i = 0; i < size; ++i) {
    const std::size_t shift = 8 * (big_endian_ ? size - 1 - i : i);
    bytes_.push_back(static_cast<std::uint8_t>((v >> shift) & 0xFFU));
  }
}

void CdrWriter::u8(std::uint8_t v) { bytes_.push_back(v); }
void CdrWriter::u32(std::uint32_t v) { put(v, 4); }
void CdrWriter::f64(double v) { put(std::bit_cast<std::uint64_t>(v), 8); }

void CdrWriter::string(const std::string& v) {
  u32(static_cast<std::uint32_t>(v.size() + 1));
  bytes_.insert(bytes_.end(), v.begin(), v.end());
  bytes_.push_back(0);
}

void CdrWriter::octets(std::span<const std::uint8_t> v) { bytes_.insert(bytes_.end(), v.begin(), v.end()); }

namespace {

void time(CdrWriter& w, const rosbag::RosTime& t) {
  w.i32(t.sec);
  w.u32(t.nanosec);
}

void header(CdrWriter& w, const rosbag::RosHeader& h) {
  time(w, h.stamp);
  w.string(h.frame_id);
}

void vector3(CdrWriter& w, const rosbag::RosVector3& v) {
  w.f64(v.x);
  w.f64(v.y);
  w.f64(v.z);
}

void quaternion(CdrWriter& w, const rosbag::RosQuaternion& q) {
  w.f64(q.x);
  w.f64(q.y);
  w.f64(q.z);
  w.f64(q.w);
}

void check(int rc, sqlite3* db, const char* what) {
  ASSERT_TRUE(rc == SQLITE_OK || rc == SQLITE_DONE) << what << ": " << sqlite3_errmsg(db);
}

void exec(sqlite3* db, const std::string& sql) {
  check(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), db, sql.c_str());
}

}  // namespace

std::vector<std::uint8_t> encodeVelodyneScan(const rosbag::VelodyneScanMessage& m, bool big_endian) {
  CdrWriter w(big_endian);
  header(w, m.header);
  w.u32(static_cast<std::uint32_t>(m.packets.size()));
  for (const auto& p : m.packets) {
    time(w, p.stamp);
    w.octets(p.data);
  }
  return w.bytes();
}

std::vector<std::uint8_t> encodeOdometry(const rosbag::OdometryMessage& m, bool big_endian) {
  CdrWriter w(big_endian);
  header(w, m.header);
  w.string(m.child_frame_id);
  vector3(w, m.position);
  quaternion(w, m.orientation);
  for (double c : m.pose_covariance) w.f64(c);
  vector3(w, m.linear_velocity);
  vector3(w, m.angular_velocity);
  for (double c : m.twist_covariance) w.f64(c);
  return w.bytes();
}

std::vector<std::uint8_t> encodeTfMessage(const rosbag::TfMessage& m, bool big_endian) {
  CdrWriter w(big_endian);
  w.u32(static_cast<std::uint32_t>(m.transforms.size()));
  for (const auto& t : m.transforms) {
    header(w, t.header);
    w.string(t.child_frame_id);
    vector3(w, t.translation);
    quaternion(w, t.rotation);
  }
  return w.bytes();
}

void writeTestBag(const std::filesystem::path& dir, const std::vector<TestBagTopic>& topics,
                  const std::vector<std::vector<TestBagMessage>>& files, bool with_metadata) {
  std::filesystem::create_directories(dir);
  std::string listed;
  for (std::size_t f = 0; f < files.size(); ++f) {
    const std::string name = "bag_" + std::to_string(f) + ".db3";
    listed += "    - " + name + "\n";
    const auto path = dir / name;
    std::filesystem::remove(path);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    // The tables as rosbag2's sqlite3 storage creates them (schema version 3).
    exec(db, "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY,ros_distro TEXT NOT NULL)");
    exec(db,
         "CREATE TABLE metadata(id INTEGER PRIMARY KEY,metadata_version INTEGER NOT NULL,metadata TEXT NOT "
         "NULL)");
    exec(db,
         "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,"
         "serialization_format TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL)");
    exec(db,
         "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL, "
         "data BLOB NOT NULL)");
    exec(db, "CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
    sqlite3_stmt* s = nullptr;
    // Topic ids differ between files on purpose (a recorder numbers them per file): 10 + index + file.
    ASSERT_EQ(sqlite3_prepare_v2(db, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", -1, &s, nullptr),
              SQLITE_OK);
    for (std::size_t i = 0; i < topics.size(); ++i) {
      sqlite3_bind_int64(s, 1, static_cast<sqlite3_int64>(10 + i + f));
      sqlite3_bind_text(s, 2, topics[i].name.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(s, 3, topics[i].type.c_str(), -1, SQLITE_TRANSIENT);
      check(sqlite3_step(s), db, "insert topic");
      sqlite3_reset(s);
    }
    sqlite3_finalize(s);
    exec(db, "BEGIN");
    ASSERT_EQ(sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1,
                                 &s, nullptr),
              SQLITE_OK);
    for (const TestBagMessage& m : files[f]) {
      std::size_t index = 0;
      while (index < topics.size() && topics[index].name != m.topic) ++index;
      ASSERT_LT(index, topics.size()) << m.topic;
      sqlite3_bind_int64(s, 1, static_cast<sqlite3_int64>(10 + index + f));
      sqlite3_bind_int64(s, 2, m.timestamp_ns);
      sqlite3_bind_blob(s, 3, m.data.data(), static_cast<int>(m.data.size()), SQLITE_TRANSIENT);
      check(sqlite3_step(s), db, "insert message");
      sqlite3_reset(s);
    }
    sqlite3_finalize(s);
    exec(db, "COMMIT");
    sqlite3_close(db);
  }
  if (!with_metadata) return;
  std::ofstream meta(dir / "metadata.yaml");
  meta << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
       << "  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n"
       << listed;
}

std::vector<CapturedPacket> capturedPackets(const std::filesystem::path& pcap, std::size_t n) {
  namespace ds = ogf::driver_sources;
  std::vector<CapturedPacket> out;
  auto reader = ds::PcapFileReader::open(pcap);
  if (!reader) return out;
  ds::PcapRecord record;
  ds::ReadStatus st;
  while (out.size() < n && (st = (*reader)->next(record)) != ds::ReadStatus::End &&
         st != ds::ReadStatus::Error) {
    if (st == ds::ReadStatus::Datagram && record.datagram.destination_port == 2368)
      out.push_back(
          {record.datagram.utime, {record.datagram.payload.begin(), record.datagram.payload.end()}});
  }
  return out;
}

const std::vector<TestBagTopic> kSampleTopics{{"/velodyne_packets", std::string(rosbag::kVelodyneScanType)},
                                              {"/odom", std::string(rosbag::kOdometryType)},
                                              {"/tf", std::string(rosbag::kTfMessageType)},
                                              {"/imu/data", "sensor_msgs/msg/Imu"}};

namespace {

rosbag::RosTime rosTimeOf(std::int64_t utime) {
  return {static_cast<std::int32_t>(utime / 1'000'000),
          static_cast<std::uint32_t>(utime % 1'000'000) * 1000U};
}

rosbag::OdometryMessage odometryAt(int i, std::int64_t utime) {
  rosbag::OdometryMessage m;
  m.header = {rosTimeOf(utime), "odom"};
  m.child_frame_id = "base_link";
  m.position = {0.1 * i, -0.01 * i * i, 1.0 / 3.0};
  const double half = 0.005 * i;
  m.orientation = {0.0, 0.0, std::sin(half), std::cos(half)};
  return m;
}

}  // namespace

WrittenBag writeSampleBag(const std::filesystem::path& dir, const std::vector<CapturedPacket>& packets,
                          bool split, bool with_metadata) {
  WrittenBag w;
  w.packets = packets;
  if (packets.empty()) return w;
  std::vector<TestBagMessage> messages;
  constexpr std::size_t kPerMessage = 38;
  for (std::size_t first = 0; first < packets.size(); first += kPerMessage) {
    rosbag::VelodyneScanMessage scan;
    scan.header = {rosTimeOf(packets[first].utime), "velodyne"};
    const std::size_t end = std::min(first + kPerMessage, packets.size());
    for (std::size_t i = first; i < end; ++i)
      scan.packets.push_back({rosTimeOf(packets[i].utime), packets[i].payload});
    messages.push_back({"/velodyne_packets", packets[end - 1].utime * 1000 + 17, encodeVelodyneScan(scan)});
  }
  const std::int64_t t0 = packets.front().utime - 20'000, t1 = packets.back().utime + 20'000;
  int i = 0;
  for (std::int64_t t = t0; t <= t1; t += 20'000, ++i) {
    w.odometry.push_back(odometryAt(i, t));
    messages.push_back({"/odom", t * 1000 + 300, encodeOdometry(w.odometry.back())});
    rosbag::TfMessage tf;
    const rosbag::TransformStampedMessage body{
        {rosTimeOf(t + 5), "odom"}, "base_link", {0.02 * i, 0.5, 0.25}, {0, 0, 0, 1}};
    w.base_link_tf.push_back(body);
    tf.transforms.push_back(body);
    tf.transforms.push_back({{rosTimeOf(t + 5), "base_link"}, "velodyne", {0.2, 0, 0.8}, {0, 0, 0, 1}});
    if (i % 5 == 0)
      tf.transforms.push_back({{rosTimeOf(t + 6), "map"}, "/base_link", {9, 9, 9}, {0, 0, 0, 1}});
    messages.push_back({"/tf", t * 1000 + 400, encodeTfMessage(tf)});
  }
  for (int k = 0; k < 3; ++k)
    messages.push_back({"/imu/data", t0 * 1000 + k, {0x00, 0x01, 0x00, 0x00, 0x2a}});
  std::vector<std::vector<TestBagMessage>> files(1);
  if (split) {
    std::stable_sort(messages.begin(), messages.end(), [](const TestBagMessage& a, const TestBagMessage& b) {
      return a.timestamp_ns < b.timestamp_ns;
    });
    files.assign(2, {});
    for (std::size_t k = 0; k < messages.size(); ++k)
      files[k < messages.size() / 2 ? 0 : 1].push_back(messages[k]);
  } else {
    files[0] = std::move(messages);
  }
  writeTestBag(dir, kSampleTopics, files, with_metadata);
  return w;
}

}  // namespace ogf::testing
