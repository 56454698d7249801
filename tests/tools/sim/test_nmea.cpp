// NMEA: the checksum and the GPRMC sentence the position packets carry.
#include <gtest/gtest.h>

#include <cstdlib>

#include "ogf/sim/nmea.hpp"
#include "ogf/sim/position_packet.hpp"

namespace ogf::sim {
namespace {

TEST(SimNmea, ChecksumOfTheTextbookSentence) {
  // The NMEA 0183 example "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A".
  EXPECT_EQ(nmeaChecksum("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W"), 0x6A);
}

TEST(SimNmea, GprmcCarriesTheUtcSecondDateAndAValidChecksum) {
  // 2024-01-01 12:34:56.789 UTC: the receiver reports the second of the last PPS edge.
  const std::int64_t utime = (1704110400LL + 34 * 60 + 56) * 1000000 + 789000;
  const std::string s = gprmcSentence(utime);
  ASSERT_GE(s.size(), 10u);
  EXPECT_EQ(s.rfind("$GPRMC,123456,A,", 0), 0u) << s;
  EXPECT_NE(s.find(",010124,"), std::string::npos) << s;
  EXPECT_EQ(s.substr(s.size() - 2), "\r\n");
  const auto star = s.find('*');
  ASSERT_NE(star, std::string::npos);
  const auto stated = std::strtoul(s.substr(star + 1, 2).c_str(), nullptr, 16);
  EXPECT_EQ(stated, nmeaChecksum(std::string_view(s).substr(1, star - 1))) << s;
}

TEST(SimPositionPacket, StampPpsAndSentenceAtTheirOffsets) {
  const std::string nmea = gprmcSentence(1704110400LL * 1000000);
  const auto p = vlp16::encodePositionPacket(0x0A0B0C0D, vlp16::kPpsLocked, nmea);
  EXPECT_EQ(p.size(), 512u);
  EXPECT_EQ(p[198], 0x0D);
  EXPECT_EQ(p[199], 0x0C);
  EXPECT_EQ(p[200], 0x0B);
  EXPECT_EQ(p[201], 0x0A);
  EXPECT_EQ(p[202], 2);
  EXPECT_EQ(std::string(p.begin() + 206, p.begin() + 206 + static_cast<std::ptrdiff_t>(nmea.size())), nmea);
  EXPECT_EQ(p[206 + nmea.size()], 0);
  for (std::size_t i = 0; i < 198; ++i) ASSERT_EQ(p[i], 0) << i;
}

}  // namespace
}  // namespace ogf::sim
