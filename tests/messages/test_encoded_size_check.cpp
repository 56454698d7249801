// The count check refuses buffers whose array counts cannot be true (too large for the bytes present,
// negative, beyond the limits) before LCM's decode() allocates for them, and never refuses a real message.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "ogf/messages/decode_message.hpp"
#include "ogf/messages/encoded_size_check.hpp"

namespace {

using ogf::messages::EncodedSizeCheck;

template <class M>
std::vector<std::uint8_t> encodedBytes(const M& m) {
  std::vector<std::uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

// Overwrites the big-endian int32 at `offset`.
void patch(std::vector<std::uint8_t>& b, std::size_t offset, std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) b[offset + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (24 - 8 * i));
}

// Finds the offset of the count field: the one int32 whose value is `count` right before the arrays
// (the check's own walk is what is being tested, so locate it independently by value).
std::size_t countOffset(const std::vector<std::uint8_t>& b, std::int32_t count, std::size_t from) {
  for (std::size_t o = from; o + 4 <= b.size(); ++o) {
    const std::int32_t v = static_cast<std::int32_t>((std::uint32_t{b[o]} << 24) | (std::uint32_t{b[o + 1]} << 16) |
                                                     (std::uint32_t{b[o + 2]} << 8) | b[o + 3]);
    if (v == count) return o;
  }
  return b.size();
}

ogf::lidar_scan_t scan(int n) {
  ogf::lidar_scan_t s{};
  s.frame_id = "velodyne_frame";
  s.packets_expected = 0x0102;  // values that cannot be mistaken for the count
  s.num_points = n;
  s.x.assign(static_cast<std::size_t>(n), 1.f);
  s.y = s.z = s.azimuth_deg = s.x;
  s.time_offset_ns.assign(static_cast<std::size_t>(n), 5);
  s.intensity.assign(static_cast<std::size_t>(n), 1);
  s.ring.assign(static_cast<std::size_t>(n), 1);
  s.laser_id = s.ring;
  s.return_type = s.ring;
  return s;
}

TEST(EncodedSizeCheck, AcceptsEveryRealScanSize) {
  for (int n : {0, 1, 7, 1000, 30000}) {
    const auto b = encodedBytes(scan(n));
    EXPECT_FALSE(EncodedSizeCheck<ogf::lidar_scan_t>::check(b.data(), b.size())) << n;
  }
}

TEST(EncodedSizeCheck, RefusesScansClaimingMorePointsThanTheyCarry) {
  auto b = encodedBytes(scan(77));
  const std::size_t at = countOffset(b, 77, 8);
  ASSERT_LT(at, b.size());
  for (std::int32_t claim : {78, 10'000'000, 2'147'483'647, -1, -2'000'000'000}) {
    auto bad = b;
    patch(bad, at, claim);
    const auto why = EncodedSizeCheck<ogf::lidar_scan_t>::check(bad.data(), bad.size());
    ASSERT_TRUE(why.has_value()) << claim;
    EXPECT_NE(why->find("num_points"), std::string::npos) << *why;
  }
  EXPECT_TRUE(EncodedSizeCheck<ogf::lidar_scan_t>::check(b.data(), 20));  // header cut
  EXPECT_TRUE(EncodedSizeCheck<ogf::lidar_scan_t>::check(b.data(), b.size() - 1));
}

TEST(EncodedSizeCheck, RefusesAbsurdDeltaPacketAndCovarianceCounts) {
  ogf::map_delta_t d{};
  d.num_cells = 5;
  d.key_x = d.key_y = d.key_z = {1, 2, 3, 4, 5};
  d.probability = {1, 2, 3, 4, 5};
  d.cell_class = {1, 0, -1, 0, 1};
  d.variance = {1, 1, 1, 1, 1};
  auto bd = encodedBytes(d);
  EXPECT_FALSE(EncodedSizeCheck<ogf::map_delta_t>::check(bd.data(), bd.size()));
  patch(bd, countOffset(bd, 5, 8), 1 << 30);
  EXPECT_TRUE(EncodedSizeCheck<ogf::map_delta_t>::check(bd.data(), bd.size()));

  ogf::velodyne_packets_t p{};
  p.sensor_address = "192.168.1.201";
  p.num_packets = 2;
  p.host_utime = {11, 12};
  p.port = {2368, 2368};
  p.length = {3, 3};
  p.num_bytes = 6;
  p.data = {1, 2, 3, 4, 5, 6};
  auto bp = encodedBytes(p);
  EXPECT_FALSE(EncodedSizeCheck<ogf::velodyne_packets_t>::check(bp.data(), bp.size()));
  auto bad_bytes = bp;
  patch(bad_bytes, countOffset(bad_bytes, 6, 8), 1'000'000'000);
  EXPECT_TRUE(EncodedSizeCheck<ogf::velodyne_packets_t>::check(bad_bytes.data(), bad_bytes.size()));
  auto bad_packets = bp;
  patch(bad_packets, countOffset(bad_packets, 2, 8), -5);
  EXPECT_TRUE(EncodedSizeCheck<ogf::velodyne_packets_t>::check(bad_packets.data(), bad_packets.size()));

  ogf::odometry_t o{};
  o.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.num_covariance = 36;
  o.covariance.assign(36, 0.5);
  auto bo = encodedBytes(o);
  EXPECT_FALSE(EncodedSizeCheck<ogf::odometry_t>::check(bo.data(), bo.size()));
  patch(bo, countOffset(bo, 36, 8), 100'000'000);
  EXPECT_TRUE(EncodedSizeCheck<ogf::odometry_t>::check(bo.data(), bo.size()));
}

// A navigation grid message's tile and column counts (found by fuzz_nav_grid_stream: a count of 2^31 tiles
// made decode() allocate 16 GB).
TEST(EncodedSizeCheck, RefusesNavGridTileAndColumnCountsBeyondTheBytes) {
  ogf::nav_grid_t g{};
  g.tile_size = 2;
  g.num_tiles = 3;
  g.tile_x = {7, 8, 9};
  g.tile_y = {7, 8, 9};
  g.num_columns = 12;
  g.cost.assign(12, 1);
  g.column_class.assign(12, 1);
  const auto good = encodedBytes(g);
  EXPECT_FALSE(EncodedSizeCheck<ogf::nav_grid_t>::check(good.data(), good.size()));
  for (const std::int32_t claim : {1 << 30, std::numeric_limits<std::int32_t>::max(), -1}) {
    auto tiles = good;
    patch(tiles, countOffset(tiles, 3, 8), claim);
    EXPECT_TRUE(EncodedSizeCheck<ogf::nav_grid_t>::check(tiles.data(), tiles.size())) << claim;
    auto columns = good;
    patch(columns, countOffset(columns, 12, 8), claim);
    EXPECT_TRUE(EncodedSizeCheck<ogf::nav_grid_t>::check(columns.data(), columns.size())) << claim;
  }
}

}  // namespace

namespace {

TEST(DecodeMessage, DecodesAValidBufferAndRefusesAbsurdCountsAndTrailingBytes) {
  ogf::odometry_t o{};
  o.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.num_covariance = 36;
  o.covariance.assign(36, 0.25);
  auto b = encodedBytes(o);
  ogf::odometry_t out{};
  EXPECT_FALSE(ogf::messages::decodeMessage(b.data(), b.size(), out));
  EXPECT_EQ(out.covariance.size(), 36u);

  auto huge = b;
  patch(huge, countOffset(huge, 36, 8), 2'147'483'647);  // would be a 16 GB vector inside decode()
  const auto why = ogf::messages::decodeMessage(huge.data(), huge.size(), out);
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("num_covariance"), std::string::npos) << *why;

  auto longer = b;
  longer.push_back(0);
  const auto trailing = ogf::messages::decodeMessage(longer.data(), longer.size(), out);
  ASSERT_TRUE(trailing.has_value());
  EXPECT_NE(trailing->find("trailing"), std::string::npos);
}

}  // namespace
