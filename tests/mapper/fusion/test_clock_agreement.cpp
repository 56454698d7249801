// ClockAgreement: scans and poses on one clock agree, on different clocks disagree, the state change is
// reported once, and the description names both clocks' times, the offset and the fix.
#include <gtest/gtest.h>

#include "ogf/fusion/clock_agreement.hpp"

namespace {

using ogf::fusion::ClockAgreement;
using ogf::fusion::ClockSample;
using ogf::fusion::ClockState;
using ogf::fusion::ScanClock;

constexpr std::int64_t kHost = 1'700'000'000'000'000;      // host clock, 2023
constexpr std::int64_t kDevice = kHost - 1'440'000'000;     // a device clock 24 min behind

TEST(ClockAgreement, UnknownWithoutPoses) {
  ClockAgreement c;
  const auto v = c.observe({ScanClock::kDevice, kDevice, kHost, std::nullopt});
  EXPECT_EQ(v.state, ClockState::kUnknown);
  EXPECT_FALSE(v.changed);
}

TEST(ClockAgreement, DeviceScansWithHostOdometryDisagreeAndNameHostAsTheFix) {
  ClockAgreement c;
  const auto v = c.observe({ScanClock::kDevice, kDevice, kHost, kHost - 20'000});
  EXPECT_EQ(v.state, ClockState::kDisagree);
  EXPECT_TRUE(v.changed);
  EXPECT_EQ(v.offset_us, kDevice - kHost + 20'000);
  const std::string d = c.describe();
  EXPECT_NE(d.find("different clocks"), std::string::npos) << d;
  EXPECT_NE(d.find("time_base: host"), std::string::npos) << d;
  EXPECT_NE(d.find(ogf::fusion::isoUtc(kDevice)), std::string::npos) << d;
  EXPECT_NE(d.find(ogf::fusion::isoUtc(kHost)), std::string::npos) << d;
  EXPECT_NE(d.find("-1439.980 s"), std::string::npos) << d;
  // The same state again is no change.
  EXPECT_FALSE(c.observe({ScanClock::kDevice, kDevice + 100'000, kHost + 100'000, kHost + 80'000}).changed);
}

TEST(ClockAgreement, OdometryOnNeitherClockSaysHowToStampIt) {
  ClockAgreement c;
  c.observe({ScanClock::kHost, kHost, kDevice, 1'000'000});
  const std::string d = c.describe();
  EXPECT_NE(d.find("matches neither clock"), std::string::npos) << d;
  EXPECT_NE(d.find("CLOCK_REALTIME"), std::string::npos) << d;
}

TEST(ClockAgreement, AgreeingAgainIsAChange) {
  ClockAgreement c;
  c.observe({ScanClock::kDevice, kDevice, kHost, kHost});
  const auto v = c.observe({ScanClock::kHost, kHost + 100'000, kDevice + 100'000, kHost + 90'000});
  EXPECT_EQ(v.state, ClockState::kAgree);
  EXPECT_TRUE(v.changed);
  EXPECT_EQ(v.offset_us, 10'000);
}

TEST(ClockAgreement, ToleranceIsTheBoundary) {
  ClockAgreement c(5'000'000);
  EXPECT_EQ(c.observe({ScanClock::kHost, kHost, kDevice, kHost - 5'000'000}).state, ClockState::kAgree);
  EXPECT_EQ(c.observe({ScanClock::kHost, kHost, kDevice, kHost - 5'000'001}).state, ClockState::kDisagree);
}

TEST(ClockAgreement, IsoUtc) {
  EXPECT_EQ(ogf::fusion::isoUtc(0), "1970-01-01T00:00:00.000Z");
  EXPECT_EQ(ogf::fusion::isoUtc(1'500'000), "1970-01-01T00:00:01.500Z");
}

}  // namespace
