// The clock of the odometry ogf-replay publishes: `auto` follows the capture's position packets as the
// driver does (the real capture without GPS gives host, the one with a PPS-locked fix gives capture); a
// pose moved to another clock keeps every other field, for both pose types the mapper reads.
#include <gtest/gtest.h>

#include <bot_core/pose_t.hpp>
#include <ogf/odometry_t.hpp>

#include <vector>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/replay/odometry_clock.hpp"
#include "ogf/replay/pose_events.hpp"
#include "support/shared_data.hpp"

namespace {

namespace ds = ogf::driver_sources;
using ogf::replay::OdometryClock;

ogf::replay::GpsTimeProbe probeCapture(const std::filesystem::path& pcap) {
  ogf::replay::GpsTimeProbe probe;
  auto reader = ds::PcapFileReader::open(pcap);
  EXPECT_TRUE(reader);
  ds::PcapRecord record;
  ds::ReadStatus st;
  while (!probe.decided() && ((st = (*reader)->next(record)) == ds::ReadStatus::Datagram || st == ds::ReadStatus::Skipped))
    if (st == ds::ReadStatus::Datagram && record.datagram.destination_port == 8308)
      probe.addPositionPayload(record.datagram.payload);
  return probe;
}

template <class Message>
std::vector<std::uint8_t> encode(const Message& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

TEST(OdometryClock, AutoIsHostForTheCaptureWithoutGpsAndCaptureForTheOneWithAPpsLockedFix) {
  OGF_REQUIRE_SHARED_FILE(no_gps, "data/real/vlp-16-test-90deg-1-50-frames.pcap");
  OGF_REQUIRE_SHARED_FILE(gps, "data/real/sampleShort.pcap");
  const auto without = probeCapture(no_gps);
  EXPECT_FALSE(without.hasGpsTime());
  EXPECT_EQ(without.positionPackets(), ogf::replay::GpsTimeProbe::kMaxPackets);  // 367 in the file: it stopped
  EXPECT_EQ(ogf::replay::resolveOdometryClock(OdometryClock::kAuto, without), OdometryClock::kHost);
  EXPECT_EQ(ogf::replay::resolveOdometryClock(OdometryClock::kCapture, without), OdometryClock::kCapture);
  const auto with = probeCapture(gps);
  EXPECT_TRUE(with.hasGpsTime());
  EXPECT_EQ(with.positionPackets(), 1);  // decided by the first locked packet
  EXPECT_EQ(ogf::replay::resolveOdometryClock(OdometryClock::kAuto, with), OdometryClock::kCapture);
  EXPECT_EQ(ogf::replay::resolveOdometryClock(OdometryClock::kHost, with), OdometryClock::kHost);
}

TEST(OdometryClock, NamesParseAndAnythingElseIsRefused) {
  EXPECT_EQ(ogf::replay::parseOdometryClock("capture"), OdometryClock::kCapture);
  EXPECT_EQ(ogf::replay::parseOdometryClock("host"), OdometryClock::kHost);
  EXPECT_EQ(ogf::replay::parseOdometryClock("auto"), OdometryClock::kAuto);
  EXPECT_FALSE(ogf::replay::parseOdometryClock("device").has_value());
  EXPECT_EQ(ogf::replay::odometryClockName(OdometryClock::kHost), "host");
}

TEST(RestampPose, AnOdometryMessageMovesItsUtimeAndKeepsEveryOtherField) {
  ogf::odometry_t m{};
  m.utime = 1'415'069'209'557'000;
  m.frame_id = "odom";
  m.child_frame_id = "base_link";
  m.position[0] = 1.5;
  m.position[2] = -0.25;
  m.orientation[0] = 0.5;
  m.orientation[3] = 0.5;
  m.num_covariance = 2;
  m.covariance = {0.1, 0.2};
  const auto moved = ogf::replay::restampPose(encode(m), [](std::int64_t t) { return t + 380'796'047'000'000; });
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  ogf::odometry_t back{};
  ASSERT_EQ(back.decode(moved->data(), 0, static_cast<int>(moved->size())), static_cast<int>(moved->size()));
  EXPECT_EQ(back.utime, m.utime + 380'796'047'000'000);
  back.utime = m.utime;
  EXPECT_EQ(encode(back), encode(m));
}

TEST(RestampPose, ABotCorePoseMovesItsUtimeAndKeepsEveryOtherField) {
  bot_core::pose_t m{};
  m.utime = 1000;
  m.pos[1] = 2.0;
  m.vel[0] = 0.5;
  m.orientation[0] = 1.0;
  m.accel[2] = 9.81;
  const auto moved = ogf::replay::restampPose(encode(m), [](std::int64_t t) { return 3 * t; });
  ASSERT_TRUE(moved.ok()) << moved.error().message;
  bot_core::pose_t back{};
  ASSERT_GT(back.decode(moved->data(), 0, static_cast<int>(moved->size())), 0);
  EXPECT_EQ(back.utime, 3000);
  back.utime = m.utime;
  EXPECT_EQ(encode(back), encode(m));
}

TEST(RestampPose, AnotherMessageTypeIsAnErrorNamingTheTypesItCouldMove) {
  const auto moved = ogf::replay::restampPose({1, 2, 3, 4, 5, 6, 7, 8, 9}, [](std::int64_t t) { return t; });
  ASSERT_FALSE(moved.ok());
  EXPECT_NE(moved.error().message.find("ogf.odometry_t nor bot_core.pose_t"), std::string::npos)
      << moved.error().message;
}

}  // namespace
