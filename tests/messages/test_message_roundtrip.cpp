// Every type of the message set survives encode/decode with empty and maximal arrays, and a truncated
// or foreign buffer is rejected instead of half-decoded.
#include <gtest/gtest.h>

#include <bot_core/pose_t.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_delta_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>
#include <ogf/odometry_t.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <cstdint>
#include <random>
#include <vector>

#include "ogf/messages/limits.hpp"

namespace {

using Rng = std::mt19937_64;

template <class T>
std::vector<T> randomVector(Rng& rng, std::size_t n) {
  std::vector<T> v(n);
  if constexpr (std::is_floating_point_v<T>) {
    std::uniform_real_distribution<T> d(T(-1000), T(1000));
    for (auto& x : v) x = d(rng);
  } else {
    std::uniform_int_distribution<long long> d(std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
    for (auto& x : v) x = static_cast<T>(d(rng));
  }
  return v;
}

// fill(msg, n, rng): every scalar set, every variable array of length n.
void fill(ogf::velodyne_packets_t& m, std::size_t n, Rng& rng) {
  m.utime = 1700000000123456;
  m.sensor_address = "192.168.1.201";
  m.num_packets = static_cast<std::int32_t>(n);
  m.host_utime = randomVector<std::int64_t>(rng, n);
  m.port = randomVector<std::int32_t>(rng, n);
  m.length.assign(n, 1206);
  m.num_bytes = static_cast<std::int32_t>(n * 1206);
  m.data = randomVector<std::uint8_t>(rng, n * 1206);
}
void fill(ogf::lidar_scan_t& m, std::size_t n, Rng& rng) {
  m.utime = 1700000000123456;
  m.seq = 42;
  m.frame_id = "velodyne";
  m.device_utime_start = 1700000000123456;
  m.device_utime_end = 1700000000223456;
  m.time_source = ogf::lidar_scan_t::TIME_SOURCE_PPS_NMEA;
  m.host_utime_start = 1700000000124000;
  m.host_utime_end = 1700000000224000;
  m.model = ogf::lidar_scan_t::MODEL_VLP16;
  m.return_mode = ogf::lidar_scan_t::RETURN_MODE_DUAL;
  m.rpm = 600.0f;
  m.cut_angle_deg = 0.0f;
  m.packets_expected = 76;
  m.packets_received = 75;
  m.packets_lost = 1;
  m.num_points = static_cast<std::int32_t>(n);
  m.x = randomVector<float>(rng, n);
  m.y = randomVector<float>(rng, n);
  m.z = randomVector<float>(rng, n);
  m.intensity = randomVector<std::uint8_t>(rng, n);
  m.ring = randomVector<std::int8_t>(rng, n);
  m.laser_id = randomVector<std::int8_t>(rng, n);
  m.azimuth_deg = randomVector<float>(rng, n);
  m.time_offset_ns = randomVector<std::int32_t>(rng, n);
  m.return_type = randomVector<std::int8_t>(rng, n);
}
void fill(ogf::odometry_t& m, std::size_t n, Rng& rng) {
  m.utime = 1700000000123456;
  m.frame_id = "odom";
  m.child_frame_id = "base_link";
  for (int i = 0; i < 3; ++i) m.position[i] = 1.5 * i;
  m.orientation[0] = 1.0;
  m.num_covariance = static_cast<std::int32_t>(n);
  m.covariance = randomVector<double>(rng, n);
}
void fill(bot_core::pose_t& m, std::size_t, Rng& rng) {
  m.utime = 1700000000123456;
  auto r = randomVector<double>(rng, 16);
  for (int i = 0; i < 3; ++i) {
    m.pos[i] = r[static_cast<std::size_t>(i)];
    m.vel[i] = r[static_cast<std::size_t>(3 + i)];
    m.rotation_rate[i] = r[static_cast<std::size_t>(6 + i)];
    m.accel[i] = r[static_cast<std::size_t>(9 + i)];
  }
  for (int i = 0; i < 4; ++i) m.orientation[i] = r[static_cast<std::size_t>(12 + i)];
}
void fill(ogf::map_delta_t& m, std::size_t n, Rng& rng) {
  m.utime = 1700000000123456;
  m.map_id = 7;
  m.seq = 1001;
  m.base_seq = 1000;
  m.kind = ogf::map_delta_t::KIND_DELTA;
  m.part_index = 0;
  m.part_count = 1;
  m.resolution = 0.2;
  m.map_checksum = -123456789;
  m.num_cells = static_cast<std::int32_t>(n);
  m.key_x = randomVector<std::int32_t>(rng, n);
  m.key_y = randomVector<std::int32_t>(rng, n);
  m.key_z = randomVector<std::int32_t>(rng, n);
  m.probability = randomVector<std::int16_t>(rng, n);
  m.cell_class = randomVector<std::int8_t>(rng, n);
  m.variance = randomVector<float>(rng, n);
}
void fill(ogf::map_request_t& m, std::size_t, Rng&) {
  m.utime = 1700000000123456;
  m.requester = "host:1234";
  m.last_seq = 99;
}
void fill(ogf::driver_status_t& m, std::size_t, Rng&) {
  m.utime = 1700000000123456;
  m.source = "udp 0.0.0.0:2368";
  m.model = ogf::lidar_scan_t::MODEL_VLP16;
  m.return_mode = ogf::lidar_scan_t::RETURN_MODE_STRONGEST;
  m.rpm = 600.f;
  m.packet_rate_hz = 754.f;
  m.scan_rate_hz = 10.f;
  m.data_packets = 1000;
  m.position_packets = 70;
  m.packets_lost = 2;
  m.bad_size = 3;
  m.bad_block_flag = 4;
  m.foreign_sender = 5;
  m.bad_other = 6;
  m.scans_published = 13;
  m.publish_errors = 0;
  m.pps_state = ogf::driver_status_t::PPS_LOCKED;
  m.gps_fix_valid = true;
  m.nmea = "$GPRMC,214106,A,3707.8178,N,12139.2690,W,010.3,188.2,230715,013.8,E,D*05";
  m.socket_receive_buffer = 8388608;
}
void fill(ogf::mapper_status_t& m, std::size_t, Rng&) {
  m.utime = 1700000000123456;
  m.scans_in = 100;
  m.scans_dropped_behind = 1;
  m.scans_dropped_no_pose = 2;
  m.scans_late = 3;
  m.scans_rejected = 4;
  m.poses_in = 1000;
  m.poses_rejected = 5;
  m.measurements = 123456789;
  m.update_ms_last = 12.5f;
  m.update_ms_mean = 11.f;
  m.lag_ms = 30.f;
  m.cells = 100000;
  m.memory_bytes = 6400000;
  m.delta_seq = 100;
  m.keyframes_sent = 2;
  m.persistence_ok = false;
  m.persistence_error = "state directory /var/lib/ogf is read-only";
  m.map_resets = 1;
  m.commands_refused_unauthenticated = 7;
  m.commands_refused_replayed = 2;
  m.commands_refused_bad_name = 3;
  m.commands_refused_busy = 1;
  m.commands_refused_disk_space = 1;
  m.queries_refused = 4;
  m.last_requester = "planner:1234";
  m.inputs = ogf::mapper_status_t::INPUTS_WAITING_FOR_POSES;
  m.last_scan_age_s = 0.1f;
  m.last_pose_age_s = -1.0f;
  m.pose_source = ogf::mapper_status_t::POSE_SOURCE_STATIC;
  m.poses_ignored = 13;
}

// Largest array each type is specified to carry (ogf/messages/limits.hpp); fixed-size types use 0.
template <class T> std::size_t maximalLength();
template <> std::size_t maximalLength<ogf::velodyne_packets_t>() { return 1000; }  // ~1.2 MB of payload
template <> std::size_t maximalLength<ogf::lidar_scan_t>() { return ogf::messages::kMaxScanPoints; }
template <> std::size_t maximalLength<ogf::odometry_t>() { return 36; }
template <> std::size_t maximalLength<bot_core::pose_t>() { return 0; }
template <> std::size_t maximalLength<ogf::map_delta_t>() { return ogf::messages::kMaxDeltaCellsPerMessage; }
template <> std::size_t maximalLength<ogf::map_request_t>() { return 0; }
template <> std::size_t maximalLength<ogf::driver_status_t>() { return 0; }
template <> std::size_t maximalLength<ogf::mapper_status_t>() { return 0; }

template <class T>
std::vector<std::uint8_t> encode(const T& m) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

template <class T>
class MessageRoundTrip : public ::testing::Test {};

using AllTypes = ::testing::Types<ogf::velodyne_packets_t, ogf::lidar_scan_t, ogf::odometry_t,
                                  bot_core::pose_t, ogf::map_delta_t, ogf::map_request_t,
                                  ogf::driver_status_t, ogf::mapper_status_t>;
TYPED_TEST_SUITE(MessageRoundTrip, AllTypes);

TYPED_TEST(MessageRoundTrip, EmptyArraysDecodeToAnEqualMessage) {
  Rng rng(1);
  TypeParam in{};
  fill(in, 0, rng);
  const auto buf = encode(in);
  TypeParam out{};
  ASSERT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  EXPECT_EQ(encode(out), buf);
}

TYPED_TEST(MessageRoundTrip, MaximalArraysDecodeToAnEqualMessage) {
  Rng rng(2);
  TypeParam in{};
  fill(in, maximalLength<TypeParam>(), rng);
  const auto buf = encode(in);
  TypeParam out{};
  ASSERT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  EXPECT_EQ(encode(out), buf);
}

TYPED_TEST(MessageRoundTrip, TruncatedBufferIsRejected) {
  Rng rng(3);
  TypeParam in{};
  fill(in, std::min<std::size_t>(maximalLength<TypeParam>(), 50), rng);
  const auto buf = encode(in);
  // Every cut from the fingerprint to the last byte must fail, not read past the end.
  const std::size_t step = std::max<std::size_t>(1, buf.size() / 97);
  for (std::size_t len = 0; len < buf.size(); len += step) {
    std::vector<std::uint8_t> cut(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(len));
    TypeParam out{};
    EXPECT_LT(out.decode(cut.data(), 0, static_cast<int>(cut.size())), 0) << "cut at " << len;
  }
  TypeParam out{};
  EXPECT_LT(out.decode(buf.data(), 0, static_cast<int>(buf.size() - 1)), 0);
}

TYPED_TEST(MessageRoundTrip, ForeignFingerprintIsRejected) {
  // A map_request_t (or a pose_t for it) decoded as this type must fail on the fingerprint.
  Rng rng(4);
  std::vector<std::uint8_t> buf;
  if constexpr (std::is_same_v<TypeParam, ogf::map_request_t>) {
    bot_core::pose_t other{};
    fill(other, 0, rng);
    buf = encode(other);
  } else {
    ogf::map_request_t other{};
    fill(other, 0, rng);
    buf = encode(other);
  }
  TypeParam out{};
  EXPECT_LT(out.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
}

TEST(MessageSet, FingerprintsAreDistinct) {
  const std::vector<std::int64_t> hashes = {
      ogf::velodyne_packets_t::getHash(), ogf::lidar_scan_t::getHash(), ogf::odometry_t::getHash(),
      bot_core::pose_t::getHash(),        ogf::map_delta_t::getHash(),  ogf::map_request_t::getHash(),
      ogf::driver_status_t::getHash(),    ogf::mapper_status_t::getHash()};
  for (std::size_t i = 0; i < hashes.size(); ++i)
    for (std::size_t j = i + 1; j < hashes.size(); ++j) EXPECT_NE(hashes[i], hashes[j]) << i << " vs " << j;
}

TEST(MessageSet, BotCorePoseHasLibbot2Layout) {
  // libbot2's pose_t: int64 utime, then 16 doubles (pos 3, vel 3, orientation 4, rotation_rate 3,
  // accel 3) = 8 (fingerprint) + 8 + 16*8 bytes. A field added or reordered changes both.
  bot_core::pose_t p{};
  EXPECT_EQ(p.getEncodedSize(), 8 + 8 + 16 * 8);
  EXPECT_STREQ(bot_core::pose_t::getTypeName(), "pose_t");
}

TEST(MessageSet, BotCorePoseFingerprintMatchesLibbot2) {
  // lcm-gen hashes member names, types and dimensions only (not package or struct name), starting from
  // 0x12345678. Recomputed by hand for libbot2's list (utime int64_t; pos[3], vel[3], orientation[4],
  // rotation_rate[3], accel[3] double) that base is 0x170b77d82958082f; the fingerprint on the wire is
  // that base rotated left by one bit for a type with no nested structs.
  constexpr std::uint64_t base = 0x170b77d82958082fULL;
  constexpr std::uint64_t expected = (base << 1) | (base >> 63);
  EXPECT_EQ(static_cast<std::uint64_t>(bot_core::pose_t::getHash()), expected);
}

TEST(MessageSet, MaximalDeltaFitsOneUdpDatagram) {
  Rng rng(5);
  ogf::map_delta_t m{};
  fill(m, ogf::messages::kMaxDeltaCellsPerMessage, rng);
  const std::string channel = "OGF_MAP_DELTA";
  EXPECT_LE(static_cast<std::size_t>(m.getEncodedSize()) + channel.size() + 1,
            ogf::messages::kMaxUnfragmentedMessageBytes);
}

}  // namespace
