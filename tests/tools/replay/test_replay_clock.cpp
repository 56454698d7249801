// ogf-replay's pacing: capture time over speed from one origin (no drift), the rate limit, loops, and a
// capture clock stepping back.
#include <gtest/gtest.h>

#include "ogf/replay/destination_ports.hpp"
#include "ogf/replay/replay_clock.hpp"

namespace {

using ogf::replay::ReplayClock;

TEST(ReplayClock, DueTimeIsCaptureTimeSinceTheFirstDividedBySpeed) {
  ReplayClock c({4.0, 0.0});
  EXPECT_EQ(c.duePacket(1'000'000), 0);
  EXPECT_EQ(c.duePacket(1'004'000), 1'000);
  EXPECT_EQ(c.duePacket(2'000'000), 250'000);
}

TEST(ReplayClock, DueTimesComeFromTheOriginNotFromThePreviousPacketSoRoundingNeverAccumulates) {
  ReplayClock c({3.0, 0.0});
  c.setOrigin(0);
  std::int64_t due = 0;
  for (int i = 1; i <= 30000; ++i) due = c.duePacket(i * 1327);  // 1327 us / 3 = 442.33 us each
  EXPECT_EQ(due, 30000LL * 1327 / 3);  // 13'270'000, exactly: no per-step rounding error summed up
}

TEST(ReplayClock, SpeedZeroSendsEverythingAtOnce) {
  ReplayClock c({0.0, 0.0});
  EXPECT_EQ(c.duePacket(5), 0);
  EXPECT_EQ(c.duePacket(5'000'000), 0);
}

TEST(ReplayClock, TheRateLimitSpacesPacketsThatTheCaptureBunches) {
  ReplayClock c({1.0, 1000.0});  // at most one packet per ms
  EXPECT_EQ(c.duePacket(0), 0);
  EXPECT_EQ(c.duePacket(10), 1000);
  EXPECT_EQ(c.duePacket(20), 2000);
  EXPECT_EQ(c.duePacket(10'000), 10'000);  // the capture's own spacing is wider: it wins
}

TEST(ReplayClock, AClockSteppingBackIsHeldNotWaitedForInThePast) {
  ReplayClock c({1.0, 0.0});
  EXPECT_EQ(c.duePacket(0), 0);
  EXPECT_EQ(c.duePacket(5000), 5000);
  EXPECT_EQ(c.duePacket(1000), 5000);
}

TEST(ReplayClock, TheNextLoopStartsWhereThisOneEndedPlusTheGap) {
  ReplayClock c({2.0, 0.0});
  c.duePacket(0);
  c.duePacket(1'000'000);  // due 500 ms
  c.nextLoop(100'000);
  EXPECT_EQ(c.duePacket(0), 600'000);
  EXPECT_EQ(c.duePacket(1'000'000), 1'100'000);
}

TEST(ReplayClock, EventsBeforeTheFirstPacketFollowTheOriginSet) {
  ReplayClock c({1.0, 1.0});  // the rate limit applies to packets only
  c.setOrigin(1'000);
  EXPECT_EQ(c.dueEvent(1'000), 0);
  EXPECT_EQ(c.duePacket(3'000), 2'000);
  EXPECT_EQ(c.dueEvent(4'000), 3'000);
}

TEST(DestinationPorts, DataAndPositionPacketsAreRedirectedOthersKeepTheirPort) {
  const ogf::replay::DestinationPorts p{12368, 18308};
  EXPECT_EQ(p.forCaptured(2368), 12368);
  EXPECT_EQ(p.forCaptured(8308), 18308);
  EXPECT_EQ(p.forCaptured(2369), 2369);
}

}  // namespace
