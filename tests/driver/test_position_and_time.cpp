// NMEA sentences with checksums, position packets, and device time from the top-of-hour counter.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "ogf/velodyne/device_clock.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "synthetic_packet.hpp"
#include "ogf/velodyne/position_packet.hpp"

namespace ov = ogf::velodyne;

namespace {
constexpr const char* kRmc = "$GPRMC,214106,A,3707.8178,N,12139.2690,W,010.3,188.2,230715,013.8,E,D*05";
constexpr std::int64_t kHourUs = 3'600'000'000LL;

std::vector<std::uint8_t> positionPacket(std::uint32_t toh, std::uint8_t pps, const char* nmea) {
  std::vector<std::uint8_t> p(512, 0);
  for (int i = 0; i < 4; ++i)
    p[198 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(toh >> (8 * i));
  p[202] = pps;
  std::memcpy(p.data() + 206, nmea, std::strlen(nmea));
  p[206 + std::strlen(nmea)] = '\r';
  return p;
}
}  // namespace

TEST(Nmea, RmcWithGoodChecksumParsesTimeDateAndFix) {
  const auto fix = ov::parseNmeaSentence(std::string(kRmc) + "\r\n");
  ASSERT_TRUE(fix) << fix.error().message;
  EXPECT_TRUE(fix->fix_valid);
  EXPECT_EQ(fix->hour, 21);
  EXPECT_EQ(fix->minute, 41);
  EXPECT_EQ(*fix->year, 2015);
  EXPECT_EQ(*fix->utcMicroseconds(), (1437685200LL + 41 * 60 + 6) * 1'000'000);
  EXPECT_NEAR(*fix->course_deg, 188.2, 1e-9);
}

TEST(Nmea, WrongOrMissingChecksumIsRefused) {
  std::string bad = kRmc;
  bad[10] = '7';  // one digit of the time changed
  const auto wrong = ov::parseNmeaSentence(bad);
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().message.find("checksum"), std::string::npos);
  EXPECT_FALSE(
      ov::parseNmeaSentence("$GPRMC,214106,A,3707.8178,N,12139.2690,W,010.3,188.2,230715,013.8,E,D"));
}

TEST(Nmea, GgaQualityDecidesTheFix) {
  const auto good =
      ov::parseNmeaSentence("$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47");
  ASSERT_TRUE(good) << good.error().message;
  EXPECT_TRUE(good->fix_valid);
  EXPECT_FALSE(good->year);
  EXPECT_NEAR(*good->latitude_deg, 48.0 + 7.038 / 60, 1e-9);
  const auto none = ov::parseNmeaSentence("$GPGGA,123519,,,,,0,00,,,M,,M,,*6B");
  ASSERT_TRUE(none) << none.error().message;
  EXPECT_FALSE(none->fix_valid);
}

TEST(PositionPacket, ReadsTimestampPpsAndSentence) {
  const auto bytes = positionPacket(2467108343u, 2, kRmc);
  const auto p = ov::parsePositionPacket(bytes);
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->toh_us, 2467108343u);
  EXPECT_EQ(p->pps, ov::PpsState::Locked);
  EXPECT_EQ(p->nmea(), kRmc);
  EXPECT_TRUE(p->gpsFixValid());
}

TEST(PositionPacket, WrongSizeAndBadPpsAreRefusedButACorruptSentenceIsNot) {
  std::vector<std::uint8_t> short_packet(100, 0);
  EXPECT_FALSE(ov::parsePositionPacket(short_packet));
  auto bad_pps = positionPacket(0, 7, kRmc);
  EXPECT_FALSE(ov::parsePositionPacket(bad_pps));
  auto corrupt = positionPacket(0, 2, "$GPRMC,214106,A,garbage*00");
  const auto p = ov::parsePositionPacket(corrupt);
  ASSERT_TRUE(p);
  EXPECT_FALSE(p->fix);
  EXPECT_FALSE(p->gpsFixValid());
}

TEST(DeviceClock, HostHourFollowsTheThirtyMinuteRule) {
  const std::int64_t hour = 1000 * kHourUs;
  // Host just after the hour, device counter just before it: the previous hour.
  EXPECT_EQ(ov::placeInHour(3599'000'000u, hour + 10'000'000), hour - 1'000'000);
  // Host just before the hour, device just after: the next hour.
  EXPECT_EQ(ov::placeInHour(5'000'000u, hour - 2'000'000), hour + 5'000'000);
  // Same hour.
  EXPECT_EQ(ov::placeInHour(1800'000'000u, hour + 1700'000'000), hour + 1800'000'000);
  ov::DeviceClock clock;
  const auto t = clock.toAbsolute(5'000'000u, hour - 2'000'000);
  EXPECT_EQ(t.source, ov::TimeSource::HostHour);
  EXPECT_EQ(t.utime, hour + 5'000'000);
}

TEST(DeviceClock, LockedPpsTakesTheHourFromNmeaNotTheHost) {
  ov::DeviceClock clock;
  const std::int64_t host = 2'000'000'000'000'000LL;  // a host clock years after the GPS time (2033): a replay
  const auto packet = ov::parsePositionPacket(positionPacket(2466500000u, 2, kRmc));
  ASSERT_TRUE(packet);
  clock.onPositionPacket(*packet, host);
  const auto t = clock.toAbsolute(2467000000u, host + 500'000);
  EXPECT_EQ(t.source, ov::TimeSource::PpsNmea);
  EXPECT_EQ(t.utime, 1437685200LL * 1'000'000 + 2467000000LL);
  // Without lock the host hour is used.
  ov::DeviceClock unlocked;
  unlocked.onPositionPacket(*ov::parsePositionPacket(positionPacket(2466500000u, 1, kRmc)), host);
  EXPECT_EQ(unlocked.toAbsolute(2467000000u, host).source, ov::TimeSource::HostHour);
  // A stale GPS time no longer anchors the hour.
  EXPECT_EQ(clock.toAbsolute(2467000000u, host + 60'000'000).source, ov::TimeSource::HostHour);
}

namespace {
// Scans from a VLP-16 stream of `packets` data packets (600 rpm: 4.8 degrees and 1327.104 us each) whose
// first position packet (PPS locked, kRmc) arrives after packet `first_position`, then every 14th, with
// the host clock in 2033, years after the GPS time.
std::vector<ov::Scan> scansWithLateFirstPositionPacket(int clock_settle_packets, int packets, int first_position) {
  ov::StreamConfig config;
  config.model = ov::Model::Vlp16;
  config.clock_settle_packets = clock_settle_packets;
  auto stream = ov::PacketStream::create(config);
  EXPECT_TRUE(stream) << stream.error().message;
  std::vector<ov::Scan> scans;
  stream->setScanSink([&](const ov::Scan& s) { scans.push_back(s); });
  const std::int64_t host0 = 2'000'000'000'000'000LL;
  const std::uint32_t toh0 = 2466500000u;
  for (int k = 0; k < packets; ++k) {
    const auto toh = static_cast<std::uint32_t>(toh0 + static_cast<std::uint32_t>(k * 1327.104));
    const std::int64_t host = host0 + static_cast<std::int64_t>(k * 1327.104);
    ogf::testing::SyntheticPacket p(toh);
    p.azimuths(k * 480 % 36000, 40).allChannels(5000, 10);
    stream->addDataPacket(p.bytes(), host);
    if (k >= first_position && (k - first_position) % 14 == 0) {
      EXPECT_TRUE(stream->addPositionPacket(positionPacket(toh, 2, kRmc), host));
    }
  }
  stream->finish();
  return scans;
}
}  // namespace

TEST(PacketStream, FirstScanWaitsForThePositionPacketSoEveryScanIsOnTheGpsTimeBase) {
  const auto scans = scansWithLateFirstPositionPacket(64, 300, 10);
  ASSERT_GE(scans.size(), 4u);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    EXPECT_EQ(scans[i].time_source, ov::TimeSource::PpsNmea) << "scan " << i;
    if (i > 0) {
      const std::int64_t step = scans[i].device_utime_start - scans[i - 1].device_utime_start;
      EXPECT_GT(step, 0) << "scan " << i;
      EXPECT_LT(step, 200'000) << "scan " << i << " is " << step << " us after the one before";
    }
  }
  // The contrast: stamping from the first packet puts the first scan on the host's hour, years away.
  const auto unsettled = scansWithLateFirstPositionPacket(0, 300, 10);
  ASSERT_GE(unsettled.size(), 2u);
  EXPECT_EQ(unsettled.front().time_source, ov::TimeSource::HostHour);
  EXPECT_GT(std::abs(unsettled[1].device_utime_start - unsettled[0].device_utime_start), kHourUs);
}

TEST(PacketStream, WithoutPositionPacketsTheHostHourTakesOverAfterTheSettleWindowAndNothingIsLost) {
  const auto held = scansWithLateFirstPositionPacket(64, 300, 1'000'000);
  const auto immediate = scansWithLateFirstPositionPacket(0, 300, 1'000'000);
  ASSERT_EQ(held.size(), immediate.size());
  for (std::size_t i = 0; i < held.size(); ++i) {
    EXPECT_EQ(held[i].time_source, ov::TimeSource::HostHour);
    EXPECT_EQ(held[i].device_utime_start, immediate[i].device_utime_start);
    EXPECT_EQ(held[i].points.size(), immediate[i].points.size());
  }
}

TEST(PacketStream, AnAbsurdSettleWindowIsRefused) {
  ov::StreamConfig config;
  config.clock_settle_packets = 100'000;
  EXPECT_FALSE(ov::PacketStream::create(config));
}

namespace {
// "$<body>*hh" with the NMEA checksum of body.
std::string withChecksum(const std::string& body) {
  unsigned x = 0;
  for (char c : body) x ^= static_cast<unsigned char>(c);
  char hex[3];
  std::snprintf(hex, sizeof(hex), "%02X", x);
  return "$" + body + "*" + hex;
}
}  // namespace

TEST(DeviceClock, AGpsTimeFarAheadOfTheHostIsRefusedAndTheHourStaysTheHosts) {
  const std::int64_t host = 1'750'000'000'000'000LL;  // 2025
  // Well formed, checksum right, PPS locked, dated 2099.
  const std::string forged = withChecksum("GPRMC,120000,A,3707.8178,N,12139.2690,W,010.3,188.2,010199,013.8,E,D");
  const auto packet = ov::parsePositionPacket(positionPacket(1000u, 2, forged.c_str()));
  ASSERT_TRUE(packet);
  ASSERT_TRUE(packet->gpsFixValid());
  ov::DeviceClock clock;
  EXPECT_FALSE(clock.onPositionPacket(*packet, host));
  const auto t = clock.toAbsolute(1000u, host);
  EXPECT_EQ(t.source, ov::TimeSource::HostHour);
  EXPECT_LT(std::abs(t.utime - host), kHourUs);
  // The stream counts it and keeps the packet (its PPS state and sentence stand).
  ov::StreamConfig config;
  config.model = ov::Model::Vlp16;
  auto stream = ov::PacketStream::create(config);
  ASSERT_TRUE(stream);
  EXPECT_TRUE(stream->addPositionPacket(positionPacket(1000u, 2, forged.c_str()), host));
  EXPECT_TRUE(stream->addPositionPacket(positionPacket(2000u, 2, kRmc), host));  // 2015: a replay, accepted
  EXPECT_EQ(stream->counters().nmea_time_refused, 1);
  EXPECT_EQ(stream->counters().position_packets, 2);
}

TEST(PositionPacket, StructureChecksRefuseRandomPacketsAndTimesPastTheHour) {
  EXPECT_FALSE(ov::parsePositionPacket(positionPacket(3'600'000'000u, 2, kRmc)));
  EXPECT_TRUE(ov::parsePositionPacket(positionPacket(3'599'999'999u, 2, kRmc)));
  auto empty = positionPacket(5u, 0, "");
  empty[206] = 0;  // no GPS: the field is all NUL
  EXPECT_TRUE(ov::parsePositionPacket(empty));
  auto garbage = empty;
  garbage[206] = 'G';
  const auto r = ov::parsePositionPacket(garbage);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().message.find("offset 206"), std::string::npos) << r.error().message;
  std::srand(24);
  int accepted = 0;
  for (int i = 0; i < 1000; ++i) {
    std::vector<std::uint8_t> p(512);
    for (auto& b : p) b = static_cast<std::uint8_t>(std::rand() & 0xFF);
    if (ov::parsePositionPacket(p)) ++accepted;
  }
  EXPECT_EQ(accepted, 0) << "random 512-byte packets taken for position packets";
  // The stream counts each kind on its own.
  ov::StreamConfig config;
  config.model = ov::Model::Vlp16;
  auto stream = ov::PacketStream::create(config);
  ASSERT_TRUE(stream);
  EXPECT_FALSE(stream->addPositionPacket(positionPacket(4'000'000'000u, 2, kRmc), 0));
  EXPECT_FALSE(stream->addPositionPacket(garbage, 0));
  EXPECT_FALSE(stream->addPositionPacket(positionPacket(5u, 9, kRmc), 0));
  EXPECT_EQ(stream->counters().bad_time_of_hour, 1);
  EXPECT_EQ(stream->counters().bad_position, 2);
  EXPECT_EQ(stream->counters().position_packets, 0);
}

TEST(PacketStream, DataPacketsWithUnknownFactoryBytesOrPastTheHourAreCountedAndNotUsed) {
  for (const bool configured : {true, false}) {
    ov::StreamConfig config;
    if (configured) config.model = ov::Model::Vlp16;
    config.clock_settle_packets = 0;
    auto stream = ov::PacketStream::create(config);
    ASSERT_TRUE(stream);
    using ogf::testing::SyntheticPacket;
    EXPECT_EQ(stream->addDataPacket(SyntheticPacket(3'600'000'000u).azimuths(0, 40).bytes(), 0),
              ov::PacketStatus::BadTimeOfHour);
    EXPECT_EQ(stream->addDataPacket(SyntheticPacket(1000u, 0x99).azimuths(0, 40).bytes(), 0),
              ov::PacketStatus::UnknownReturnMode);
    EXPECT_EQ(stream->addDataPacket(SyntheticPacket(1000u, 0x37, 0x77).azimuths(0, 40).bytes(), 0),
              ov::PacketStatus::UnknownProduct);
    EXPECT_EQ(stream->addDataPacket(SyntheticPacket(1000u, 0x00, 0x00).azimuths(0, 40).allChannels(5000, 10).bytes(), 0),
              ov::PacketStatus::Ok) << "0 is old firmware that reports neither";
    const auto& c = stream->counters();
    EXPECT_EQ(c.bad_time_of_hour, 1) << configured;
    EXPECT_EQ(c.unknown_return_mode, 1) << configured;
    EXPECT_EQ(c.unknown_model, 1) << configured;
    EXPECT_EQ(c.bad_other, 0) << configured;
  }
}
