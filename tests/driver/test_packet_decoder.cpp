// The packet decoder on hand-made packets: geometry and frame, azimuth interpolation and wrap, timing,
// return modes, and rejection of malformed packets.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "ogf/velodyne/packet_decoder.hpp"
#include "synthetic_packet.hpp"

namespace ov = ogf::velodyne;
using ogf::testing::SyntheticPacket;

namespace {

ov::PacketDecoder decoder(ov::Model model = ov::Model::Vlp16, std::optional<ov::ReturnMode> mode = {}) {
  ov::DecoderConfig c;
  c.model = model;
  c.min_range_m = 0.0;
  c.return_mode = mode;
  // Zero offsets: the textbook formulas.
  ov::Calibration calib = ov::nominalCalibration(model);
  for (auto& l : calib.lasers) l.vert_offset_m = 0.0;
  c.calibration = calib;
  return *ov::PacketDecoder::create(c);
}

double deg(double d) { return d * std::numbers::pi / 180.0; }

}  // namespace

TEST(PacketDecoder, PointsFollowRep103AndTwoMillimetreUnits) {
  const auto d = decoder();
  auto out = std::make_unique<ov::DecodedPacket>();
  // Azimuth 90 degrees (to the right, clockwise from x): a point on -y.
  SyntheticPacket p;
  p.azimuths(9000, 0).channel(0, 1, 5000, 77);  // laser 1: +1 degree, 10 m
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  ASSERT_EQ(out->point_count, 1);
  const ov::Point& pt = out->points[0];
  EXPECT_NEAR(pt.distance_m, 10.0, 1e-6);
  EXPECT_NEAR(pt.x, 0.0, 1e-4);
  EXPECT_NEAR(pt.y, -10.0 * std::cos(deg(1)), 1e-4);
  EXPECT_NEAR(pt.z, 10.0 * std::sin(deg(1)), 1e-4);
  EXPECT_EQ(pt.intensity, 77);
  EXPECT_EQ(pt.laser_id, 1);
  EXPECT_EQ(pt.ring, 8);
}

TEST(PacketDecoder, AzimuthIsInterpolatedPerFiringAndWrapped) {
  const auto d = decoder();
  auto out = std::make_unique<ov::DecodedPacket>();
  // Blocks 40 units apart, starting just below 360 degrees so the packet wraps.
  SyntheticPacket p;
  p.azimuths(35990, 40).allChannels(1000, 1);
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  ASSERT_EQ(out->point_count, 384);
  // Block 0, sequence 1, laser 15: 35990 + 40 * (55.296 + 15 * 2.304) / 110.592 = 36022.5 -> 22.5 -> 23
  // (round).
  const ov::Point& p31 = out->points[31];
  EXPECT_EQ(p31.laser_id, 15);
  EXPECT_NEAR(p31.azimuthDeg(), 0.23, 1e-4);
  EXPECT_NEAR(p31.timeOffsetUs(), 55.296 + 15 * 2.304, 1e-3);
  for (int i = 0; i < out->point_count; ++i) {
    EXPECT_GE(out->points[static_cast<std::size_t>(i)].azimuthDeg(), 0.0f);
    EXPECT_LT(out->points[static_cast<std::size_t>(i)].azimuthDeg(), 360.0f);
  }
  // The last block reuses the previous advance; time of block 11, sequence 1, laser 15.
  EXPECT_NEAR(out->points[383].timeOffsetUs(), 11 * 110.592 + 55.296 + 15 * 2.304, 1e-3);
  EXPECT_EQ(out->firing_count, 24);
}

TEST(PacketDecoder, Azimuth36000FromTheSensorIsZero) {
  const auto d = decoder();
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p;
  p.azimuths(0, 20).azimuth(0, 36000).channel(0, 0, 500, 1);
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  EXPECT_NEAR(out->points[0].azimuthDeg(), 0.0, 1e-6);
  SyntheticPacket q;
  q.azimuths(0, 20).azimuth(3, 36001);
  EXPECT_EQ(d.decode(q.bytes(), *out), ov::PacketStatus::BadAzimuth);
}

TEST(PacketDecoder, ZeroRangeIsDroppedAndRangeLimitsApply) {
  ov::DecoderConfig c;
  c.min_range_m = 1.0;
  c.max_range_m = 50.0;
  const auto d = *ov::PacketDecoder::create(c);
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p;
  p.azimuths(0, 20).channel(0, 0, 0, 9).channel(0, 1, 400, 9).channel(0, 2, 600, 9).channel(0, 3, 30000, 9);
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  ASSERT_EQ(out->point_count, 1);
  EXPECT_NEAR(out->points[0].distance_m, 1.2, 1e-6);
}

TEST(PacketDecoder, MalformedPacketsAreRejected) {
  const auto d = decoder();
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p;
  p.azimuths(0, 20);
  const auto& b = p.bytes();
  EXPECT_EQ(d.decode(std::span(b.data(), 1205), *out), ov::PacketStatus::WrongSize);
  SyntheticPacket flag;
  flag.azimuths(0, 20).byte(700, 0xDD);
  EXPECT_EQ(d.decode(flag.bytes(), *out), ov::PacketStatus::BadBlockFlag);
  EXPECT_EQ(out->point_count, 0);
}

TEST(PacketDecoder, DualPairsGiveLastStrongestOrOnePointForBoth) {
  const auto d = decoder();
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p(0, 0x39);
  p.azimuths(1000, 40, true);
  p.channel(0, 0, 1000, 10).channel(1, 0, 1000, 10);  // identical: one point, both
  p.channel(0, 1, 2000, 5).channel(1, 1, 1500, 50);   // last farther, strongest nearer
  p.channel(2, 16, 0, 0).channel(3, 16, 700, 3);      // only the strongest block has a return
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  EXPECT_EQ(out->return_mode, ov::ReturnMode::Dual);
  ASSERT_EQ(out->point_count, 4);
  EXPECT_EQ(out->points[0].return_type, ov::ReturnType::Both);
  EXPECT_EQ(out->points[1].return_type, ov::ReturnType::Last);
  EXPECT_NEAR(out->points[1].distance_m, 4.0, 1e-6);
  EXPECT_EQ(out->points[2].return_type, ov::ReturnType::Strongest);
  EXPECT_NEAR(out->points[2].distance_m, 3.0, 1e-6);
  // Pair 1, sequence 1, laser 0: time uses the pair index (one firing per pair).
  EXPECT_NEAR(out->points[3].timeOffsetUs(), 110.592 + 55.296, 1e-3);
  // The azimuth advance comes from the next pair: 1040 + 40 * 0.5 = 1060.
  EXPECT_NEAR(out->points[3].azimuthDeg(), 10.60, 1e-4);
  EXPECT_EQ(out->firing_count, 12);
}

TEST(PacketDecoder, SingleReturnModeFromTheByteOrTheConfiguration) {
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p(0, 0x38);
  p.azimuths(0, 20).channel(0, 0, 1000, 1);
  ASSERT_EQ(decoder().decode(p.bytes(), *out), ov::PacketStatus::Ok);
  EXPECT_EQ(out->points[0].return_type, ov::ReturnType::Last);
  SyntheticPacket q(0, 0x00);  // no mode byte (old HDL-32E firmware): configuration names it
  q.azimuths(0, 20).channel(0, 0, 1000, 1);
  ASSERT_EQ(decoder(ov::Model::Vlp16, ov::ReturnMode::Last).decode(q.bytes(), *out), ov::PacketStatus::Ok);
  EXPECT_EQ(out->points[0].return_type, ov::ReturnType::Last);
}

TEST(PacketDecoder, Hdl32eFiresOneLaserEvery1152NanosecondsAcrossAllChannels) {
  const auto d = decoder(ov::Model::Hdl32E);
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p(0, 0x37, 0x21);
  p.azimuths(0, 16).allChannels(2500, 1);
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  EXPECT_EQ(out->firing_count, 12);
  const ov::Point& last_in_block = out->points[31];
  EXPECT_EQ(last_in_block.laser_id, 31);
  EXPECT_NEAR(last_in_block.timeOffsetUs(), 31 * 1.152, 1e-3);
  EXPECT_NEAR(out->points[32].timeOffsetUs(), 46.08, 1e-3);
  // 16 units over 46.08 us; laser 31 at 35.712 us: 16 * 0.775 = 12.4 -> 12.
  EXPECT_NEAR(last_in_block.azimuthDeg(), 0.12, 1e-4);
  EXPECT_NEAR(last_in_block.z, 5.0 * std::sin(deg(10.67)), 1e-4);
}

TEST(PacketDecoder, Vlp32cUsesFourMillimetreUnitsAndLaserPairs) {
  const auto d = decoder(ov::Model::Vlp32C);
  auto out = std::make_unique<ov::DecodedPacket>();
  SyntheticPacket p(0, 0x37, 0x28);
  p.azimuths(0, 20).channel(1, 5, 1000, 1);
  ASSERT_EQ(d.decode(p.bytes(), *out), ov::PacketStatus::Ok);
  ASSERT_EQ(out->point_count, 1);
  EXPECT_NEAR(out->points[0].distance_m, 4.0, 1e-6);
  EXPECT_NEAR(out->points[0].timeOffsetUs(), 55.296 + 2 * 2.304, 1e-3);
}
