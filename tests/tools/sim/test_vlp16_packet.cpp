// VLP-16 data packets: bytes at the offsets of docs/wire-format.md §3.1, the firing schedule of §4.1, the
// dual layout of §5.1, and simulated ranges that match the geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ogf/sim/vlp16_packet.hpp"
#include "ogf/sim/lidar_model.hpp"
#include "ogf/sim/lidar_simulator.hpp"
#include "sim_test_world.hpp"

namespace ogf::sim {
namespace {

using vlp16::ReturnMode;

std::uint16_t le16(const std::array<std::uint8_t, vlp16::kDataPayloadBytes>& b, std::size_t at) {
  return static_cast<std::uint16_t>(b[at] | (b[at + 1] << 8));
}

TEST(SimVlp16Packet, FieldsLandAtTheDocumentedOffsetsLittleEndian) {
  vlp16::DataPacket p;
  for (std::size_t b = 0; b < 12; ++b) {
    p.blocks[b].azimuth = static_cast<std::uint16_t>(35000 + 40 * b);
    for (std::size_t c = 0; c < 32; ++c) {
      p.blocks[b].distance[c] = static_cast<std::uint16_t>(1000 * b + 7 * c + 1);
      p.blocks[b].reflectivity[c] = static_cast<std::uint8_t>(b + c);
    }
  }
  p.toh_us = 0x12345678;
  p.mode = ReturnMode::Dual;
  std::array<std::uint8_t, vlp16::kDataPayloadBytes> out{};
  vlp16::encode(p, out);
  for (std::size_t b = 0; b < 12; ++b) {
    EXPECT_EQ(out[100 * b], 0xFF) << b;
    EXPECT_EQ(out[100 * b + 1], 0xEE) << b;
    EXPECT_EQ(le16(out, 100 * b + 2), 35000 + 40 * b);
    for (std::size_t c = 0; c < 32; ++c) {
      EXPECT_EQ(le16(out, 100 * b + 4 + 3 * c), 1000 * b + 7 * c + 1);
      EXPECT_EQ(out[100 * b + 6 + 3 * c], b + c);
    }
  }
  EXPECT_EQ(out[1200], 0x78);
  EXPECT_EQ(out[1201], 0x56);
  EXPECT_EQ(out[1202], 0x34);
  EXPECT_EQ(out[1203], 0x12);
  EXPECT_EQ(out[1204], 0x39);
  EXPECT_EQ(out[1205], 0x22);
}

TEST(SimVlp16Packet, FiringScheduleAndPacketPeriodMatchTheManual) {
  EXPECT_EQ(vlp16::channelOffsetNs(0, 0), 0);
  EXPECT_EQ(vlp16::channelOffsetNs(0, 1), 2304);
  EXPECT_EQ(vlp16::channelOffsetNs(0, 15), 15 * 2304);
  EXPECT_EQ(vlp16::channelOffsetNs(0, 16), 55296);
  EXPECT_EQ(vlp16::channelOffsetNs(1, 0), 110592);
  EXPECT_EQ(vlp16::channelOffsetNs(11, 31), 11 * 110592 + 55296 + 15 * 2304);
  EXPECT_EQ(vlp16::packetPeriodNs(ReturnMode::Strongest), 1327104);
  EXPECT_EQ(vlp16::packetPeriodNs(ReturnMode::Last), 1327104);
  EXPECT_EQ(vlp16::packetPeriodNs(ReturnMode::Dual), 663552);
  EXPECT_EQ(vlp16::firingGroup(7, ReturnMode::Dual), 3);
  EXPECT_EQ(vlp16::firingGroup(7, ReturnMode::Strongest), 7);
}

class SimulatedPackets : public ::testing::TestWithParam<std::tuple<double, ReturnMode>> {};

TEST_P(SimulatedPackets, StampsFollowThePeriodAndAzimuthsTheRpm) {
  const auto [rpm, mode] = GetParam();
  const World world = test::groundOnly();
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  SensorConfig cfg;
  cfg.rpm = rpm;
  cfg.mode = mode;
  const std::int64_t start = 1704110400LL * 1000000;  // 12:00:00 UTC: TOH starts at 0
  const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, cfg, start);
  const double period_us = mode == ReturnMode::Dual ? 663.552 : 1327.104;
  const double deg_per_us = rpm * 360.0 / 60.0 * 1e-6;
  double previous_az = -1.0;
  for (std::uint64_t k = 0; k < 200; ++k) {
    const auto p = sim.dataPacket(k);
    EXPECT_EQ(p.toh_us, static_cast<std::uint32_t>(std::floor(static_cast<double>(k) * period_us + 1e-9))) << k;
    EXPECT_EQ(p.mode, mode);
    EXPECT_EQ(p.product_id, 0x22);
    for (int b = 0; b < 12; ++b) {
      const int group = vlp16::firingGroup(b, mode);
      const double t_us = static_cast<double>(k) * period_us + 110.592 * group;
      const double expected = std::fmod(t_us * deg_per_us, 360.0) * 100.0;
      const double diff = std::remainder(p.blocks[static_cast<std::size_t>(b)].azimuth - expected, 36000.0);
      EXPECT_LE(std::abs(diff), 0.5 + 1e-6) << "packet " << k << " block " << b;
      EXPECT_LT(p.blocks[static_cast<std::size_t>(b)].azimuth, 36000);
      if (mode == ReturnMode::Dual && b % 2 == 1) {
        EXPECT_EQ(p.blocks[static_cast<std::size_t>(b)].azimuth, p.blocks[static_cast<std::size_t>(b - 1)].azimuth);
      }
    }
    const double az = p.blocks[0].azimuth;
    if (previous_az >= 0) {
      EXPECT_NEAR(std::remainder(az - previous_az, 36000.0), period_us * deg_per_us * 100.0, 1.0) << k;
    }
    previous_az = az;
  }
}

INSTANTIATE_TEST_SUITE_P(RpmAndMode, SimulatedPackets,
                         ::testing::Values(std::make_tuple(600.0, ReturnMode::Strongest),
                                           std::make_tuple(1200.0, ReturnMode::Last),
                                           std::make_tuple(600.0, ReturnMode::Dual),
                                           std::make_tuple(1200.0, ReturnMode::Dual)));

TEST(SimLidarSimulator, GroundRangesMatchElevationAndVerticalOffset) {
  const World world = test::groundOnly();
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  SensorConfig cfg;
  cfg.range_noise_m = 0.0;
  const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, cfg, 0);
  const auto p = sim.dataPacket(3);
  for (std::size_t c = 0; c < 32; ++c) {
    const std::size_t laser = c % 16;
    const double w = vlp16::kElevationDeg[laser] * std::numbers::pi / 180.0;
    const auto d = p.blocks[5].distance[c];
    if (w >= 0) {
      EXPECT_EQ(d, 0) << "laser " << laser << " looks up at an empty sky";
      continue;
    }
    // The beam starts at height 1 + offset and meets z = 0 after (1 + offset) / sin(-w).
    const double range = (1.0 + vlp16::kVerticalOffsetM[laser]) / std::sin(-w);
    EXPECT_EQ(d, static_cast<std::uint16_t>(std::lround(range / 0.002))) << "laser " << laser;
    // Lambertian: reflectivity 50 times the cosine of incidence, floored at a tenth.
    EXPECT_EQ(p.blocks[5].reflectivity[c], std::lround(50.0 * std::max(0.1, std::sin(-w))));
  }
}

TEST(SimLidarSimulator, DualModeHoldsLastInEvenBlocksAndStrongestOtherInOdd) {
  for (const double glass_refl : {15.0, 220.0}) {  // glass weaker than the wall, then stronger
    const World world = test::glassBeforeWall(glass_refl);
    const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
    ASSERT_TRUE(traj.ok());
    SensorConfig cfg;
    cfg.range_noise_m = 0.0;
    cfg.mode = ReturnMode::Dual;
    const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, cfg, 0);
    const auto p = sim.dataPacket(0);  // azimuth ≈ 0: looking along +x at the pane and the wall
    const auto& last = p.blocks[0];
    const auto& strongest = p.blocks[1];
    // Laser 1 (+1°) crosses the pane at 2 m, then the wall at 5 m.
    EXPECT_NEAR(last.distance[1] * 0.002, 5.0 / std::cos(std::numbers::pi / 180.0), 0.004);
    EXPECT_NEAR(strongest.distance[1] * 0.002, 2.0 / std::cos(std::numbers::pi / 180.0) - 0.01, 0.004);
    EXPECT_NE(last.reflectivity[1], strongest.reflectivity[1]);
    // Laser 15 (+15°) passes over the 1.3 m pane: one return, both blocks identical.
    EXPECT_GT(last.distance[15], 0);
    EXPECT_EQ(last.distance[15], strongest.distance[15]);
    EXPECT_EQ(last.reflectivity[15], strongest.reflectivity[15]);
  }
}

TEST(SimLidarSimulator, StrongestAndLastModesPickTheirEcho) {
  const World world = test::glassBeforeWall(220.0);  // the pane is the strongest echo, the wall the last
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  SensorConfig cfg;
  cfg.range_noise_m = 0.0;
  const Eigen::Isometry3d mount(Eigen::Translation3d(0, 0, 1));
  cfg.mode = ReturnMode::Strongest;
  const auto strongest = LidarSimulator(world, mount, *traj, cfg, 0).dataPacket(0);
  cfg.mode = ReturnMode::Last;
  const auto last = LidarSimulator(world, mount, *traj, cfg, 0).dataPacket(0);
  EXPECT_LT(strongest.blocks[0].distance[1] * 0.002, 2.1);
  EXPECT_GT(last.blocks[0].distance[1] * 0.002, 4.9);
}

TEST(SimLidarModel, Hdl32eFiresThirtyTwoLasersPerBlockWithItsProductByte) {
  const LidarModel& m = lidarModel(LidarModelId::Hdl32e);
  EXPECT_EQ(m.lasers, 32u);
  EXPECT_EQ(m.product_id, 0x21);
  EXPECT_EQ(m.channelOffsetNs(0, 1), 1152);
  EXPECT_EQ(m.channelOffsetNs(0, 31), 31 * 1152);
  EXPECT_EQ(m.channelOffsetNs(2, 0), 2 * 46080);
  EXPECT_EQ(m.packetPeriodNs(ReturnMode::Strongest), 552960);
  EXPECT_EQ(m.packetPeriodNs(ReturnMode::Dual), 276480);
  // The VLP-16 entry is the schedule of §4.3.
  EXPECT_EQ(lidarModel(LidarModelId::Vlp16).channelOffsetNs(3, 17), vlp16::channelOffsetNs(3, 17));

  const World world = test::groundOnly();
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  SensorConfig cfg;
  cfg.model = LidarModelId::Hdl32e;
  cfg.range_noise_m = 0.0;
  const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, cfg, 0);
  EXPECT_EQ(sim.packetPeriodNs(), 552960);
  const auto p = sim.dataPacket(10);
  EXPECT_EQ(p.product_id, 0x21);
  EXPECT_EQ(p.toh_us, 5529u);  // floor(10 × 552.96 µs)
  for (std::size_t c = 0; c < 32; ++c) {
    const double w = m.elevation_deg[c] * std::numbers::pi / 180.0;
    if (w >= 0) {
      EXPECT_EQ(p.blocks[4].distance[c], 0) << "laser " << c;
    } else {
      EXPECT_EQ(p.blocks[4].distance[c], std::lround(1.0 / std::sin(-w) / 0.002)) << "laser " << c;
    }
  }
}

TEST(SimLidarSimulator, DropoutsEmptyTheirShareOfFirings) {
  const World world = test::groundOnly();
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  SensorConfig cfg;
  cfg.dropout = 0.25;
  const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, cfg, 0);
  int empty = 0;
  int total = 0;
  for (std::uint64_t k = 0; k < 50; ++k) {
    const auto p = sim.dataPacket(k);
    for (const auto& b : p.blocks) {
      for (std::size_t c = 0; c < 32; ++c) {
        if (vlp16::kElevationDeg[c % 16] >= 0) continue;  // only the lasers that would hit the ground
        ++total;
        empty += b.distance[c] == 0 ? 1 : 0;
      }
    }
  }
  EXPECT_NEAR(static_cast<double>(empty) / total, 0.25, 0.03);
}

}  // namespace
}  // namespace ogf::sim
