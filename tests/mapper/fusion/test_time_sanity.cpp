// TimeSanity: a message dated far from the host clock or from its stream is refused, counted, and never
// becomes the reference; a clock that really jumps is followed after the configured run of agreeing
// messages, forwards and backwards; a stale message after a pause of the stream never makes the resumed
// stream look ahead.
#include <ogf/fusion/time_sanity.hpp>

#include <gtest/gtest.h>

namespace ogf::fusion {
namespace {

constexpr std::int64_t kS = 1'000'000;
constexpr std::int64_t kNow = 1'750'000'000 * kS;   // the host clock in these tests
constexpr std::int64_t kYear2100 = 4'102'444'800 * kS;

// A stream at 100 Hz on the host clock, `count` messages from `start`, steady time = message time.
struct Stream {
  TimeSanity sanity{TimeSanityConfig{}};
  std::int64_t t = kNow;
  TimeVerdict next(std::int64_t step = 10'000) {
    t += step;
    return sanity.check(t, t, t);
  }
};

TEST(TimeSanity, OneMessageFromTheFutureIsRefusedAndNeverBecomesTheReference) {
  Stream s;
  for (int i = 0; i < 100; ++i) ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  EXPECT_EQ(s.sanity.check(kYear2100, s.t, s.t), TimeVerdict::kAheadOfStream);
  EXPECT_EQ(s.sanity.reference(), s.t);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(s.next(), TimeVerdict::kAccept) << i;
  EXPECT_EQ(s.sanity.counts().refused_ahead, 1);
  EXPECT_EQ(s.sanity.counts().jumps_followed, 0);
}

TEST(TimeSanity, TheFirstMessageIsCheckedAgainstTheHostClock) {
  TimeSanity sanity{TimeSanityConfig{}};
  EXPECT_EQ(sanity.check(kYear2100, kNow, 0), TimeVerdict::kAheadOfHost);
  EXPECT_FALSE(sanity.reference().has_value());
  EXPECT_EQ(sanity.check(kNow + 9 * kS, kNow, 0), TimeVerdict::kAccept) << "within max_ahead_s of the host";
  TimeSanity replay{TimeSanityConfig{}};
  EXPECT_EQ(replay.check(kNow - 3 * 365 * 86400 * kS, kNow, 0), TimeVerdict::kAccept) << "a log from the past";
}

TEST(TimeSanity, FarBehindTheStreamIsRefusedButSlightlyBehindIsLeftToTheBuffers) {
  Stream s;
  for (int i = 0; i < 10; ++i) ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  EXPECT_EQ(s.sanity.check(s.t - 5 * kS, s.t, s.t), TimeVerdict::kAccept);
  EXPECT_EQ(s.sanity.reference(), s.t) << "an older time does not move the reference back";
  EXPECT_EQ(s.sanity.check(s.t - 3600 * kS, s.t, s.t), TimeVerdict::kBehindStream);
  EXPECT_EQ(s.sanity.counts().refused_behind, 1);
}

TEST(TimeSanity, TheStreamMayRunAheadByTheHostTimeElapsed) {
  Stream s;
  ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  // Nothing for a minute, then the stream goes on a minute later: plausible.
  EXPECT_EQ(s.sanity.check(s.t + 60 * kS, s.t + 60 * kS, s.t + 60 * kS), TimeVerdict::kAccept);
  // A stream paused and resumed (a log player): behind the host, on time for itself.
  const std::int64_t host = s.t + 600 * kS;
  EXPECT_EQ(s.sanity.check(s.t + 60 * kS + 10'000, host, host), TimeVerdict::kAccept);
}

// A sensor stream at 10 Hz pauses for 15 s (longer than max_ahead_s); the driver then publishes the partial
// scan it held, dated before the pause, and the scans resume on the sensor's clock, which ran on.
TEST(TimeSanity, AStaleScanAfterAPauseLongerThanMaxAheadDoesNotMakeTheResumedScansLookAhead) {
  TimeSanity sanity{TimeSanityConfig{}};
  std::int64_t t = kNow;
  std::int64_t host = kNow;
  for (int i = 0; i < 50; ++i, t += 100'000, host += 100'000) ASSERT_EQ(sanity.check(t, host, host), TimeVerdict::kAccept);
  const std::int64_t last = t - 100'000;
  host += 15 * kS;
  t += 15 * kS;
  EXPECT_EQ(sanity.check(last + 50'000, host, host), TimeVerdict::kAccept) << "the stale partial scan";
  for (int i = 0; i < 20; ++i, t += 100'000, host += 100'000) {
    host += 1'000;  // each arrives a little after its time, as over a network
    EXPECT_EQ(sanity.check(t, host, host), TimeVerdict::kAccept) << "resumed scan " << i;
  }
  EXPECT_EQ(sanity.counts().refused(), 0);
  EXPECT_EQ(sanity.counts().jumps_followed, 0);
}

TEST(TimeSanity, AStaleMessageAfterAPauseStillLeavesAFarFutureTimeRefused) {
  Stream s;
  for (int i = 0; i < 10; ++i) ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  const std::int64_t host = s.t + 15 * kS;
  ASSERT_EQ(s.sanity.check(s.t + 5'000, host, host), TimeVerdict::kAccept);
  // The stream may have run on 15 s, plus max_ahead_s (10 s): 26 s beyond the message before the pause is
  // one second too far.
  EXPECT_EQ(s.sanity.check(s.t + 26 * kS, host, host), TimeVerdict::kAheadOfStream);
  EXPECT_EQ(s.sanity.check(kYear2100, host, host), TimeVerdict::kAheadOfStream);
  EXPECT_EQ(s.sanity.check(s.t + 24 * kS, host, host), TimeVerdict::kAccept);
  EXPECT_EQ(s.sanity.counts().refused_ahead, 2);
}

TEST(TimeSanity, TheExpectedStreamTimeIsTheNewestTimePlusTheHostTimeSince) {
  TimeSanity sanity{TimeSanityConfig{}};
  EXPECT_FALSE(sanity.expectedAt(kNow).has_value());
  ASSERT_EQ(sanity.check(kNow, kNow, kNow), TimeVerdict::kAccept);
  EXPECT_EQ(sanity.expectedAt(kNow + 2 * kS), kNow + 2 * kS);
  // A message 1 s newer arriving 5 s later: the stream is still expected where its clock ran at host pace.
  ASSERT_EQ(sanity.check(kNow + kS, kNow + 5 * kS, kNow + 5 * kS), TimeVerdict::kAccept);
  EXPECT_EQ(sanity.reference(), kNow + kS);
  EXPECT_EQ(sanity.expectedAt(kNow + 5 * kS), kNow + 5 * kS);
}

TEST(TimeSanity, ARealJumpIsFollowedAfterTheConfiguredRunForwardsAndBackwards) {
  for (const std::int64_t jump : {+86400 * kS, -86400 * kS}) {
    Stream s;
    for (int i = 0; i < 10; ++i) ASSERT_EQ(s.next(), TimeVerdict::kAccept);
    const std::int64_t before = s.t;
    std::int64_t host = s.t;
    std::int64_t t = s.t + jump;
    for (int i = 1; i < 5; ++i) {
      t += 10'000;
      host += 10'000;
      EXPECT_NE(s.sanity.check(t, host, host), TimeVerdict::kAccept) << jump << " message " << i;
    }
    t += 10'000;
    host += 10'000;
    EXPECT_EQ(s.sanity.check(t, host, host), TimeVerdict::kFollowJump) << jump;
    EXPECT_EQ(s.sanity.reference(), t);
    EXPECT_EQ(s.sanity.timeBeforeLastJump(), before);
    EXPECT_EQ(s.sanity.check(t + 10'000, host + 10'000, host + 10'000), TimeVerdict::kAccept);
    EXPECT_EQ(s.sanity.counts().refused(), 4);
    EXPECT_EQ(s.sanity.counts().jumps_followed, 1);
  }
}

TEST(TimeSanity, RefusedMessagesThatDisagreeOrAreInterleavedWithTheStreamAreNeverFollowed) {
  Stream s;
  ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  // Bad times alternating with good ones: the run restarts at every good one.
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(s.sanity.check(kYear2100 + i, s.t, s.t), TimeVerdict::kAheadOfStream);
    ASSERT_EQ(s.next(), TimeVerdict::kAccept);
  }
  // Bad times in a row that do not agree with each other (decreasing, or scattered over years).
  for (int i = 0; i < 50; ++i) {
    const std::int64_t t = i % 2 == 0 ? kYear2100 - i * kS : kYear2100 + (i % 7) * 365 * 86400 * kS;
    EXPECT_NE(s.sanity.check(t, s.t, s.t), TimeVerdict::kFollowJump) << i;
  }
  EXPECT_EQ(s.sanity.counts().jumps_followed, 0);
  EXPECT_EQ(s.sanity.counts().refused_ahead, 100);
}

TEST(TimeSanity, ConfigurationNamesTheWrongField) {
  TimeSanityConfig c;
  EXPECT_TRUE(c.validate());
  c.max_ahead_s = 0;
  EXPECT_NE(c.validate().error().message.find("max_time_ahead_s"), std::string::npos);
  c = {};
  c.max_behind_s = -1;
  EXPECT_NE(c.validate().error().message.find("max_time_behind_s"), std::string::npos);
  c = {};
  c.follow_after = 1;
  EXPECT_NE(c.validate().error().message.find("clock_jump_messages"), std::string::npos);
}

}  // namespace
}  // namespace ogf::fusion
