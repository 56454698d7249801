// What ogf-replay says at the end and about its odometry's clock: the summary line carries every count in
// its fixed order with the rate over the elapsed time, and the clock's reason names the flag or what the
// capture's position packets showed.
#include <gtest/gtest.h>

#include <string>

#include "ogf/replay/odometry_clock.hpp"
#include "ogf/replay/replay_counts.hpp"

namespace {

using ogf::replay::OdometryClock;

TEST(ReplaySummary, LineListsEveryCountInOrderWithTheRateOverTheSeconds) {
  ogf::replay::ReplayCounts counts;
  counts.data = 300;
  counts.position = 20;
  counts.other = 5;
  counts.skipped = 7;
  counts.send_errors = 2;
  counts.poses = 40;
  EXPECT_EQ(ogf::replay::summaryLine(counts, 3, 2.5),
            "packets 325 data 300 position 20 other 5 skipped 7 send_errors 2 poses 40 loops 3 seconds 2.500 "
            "rate 130.0\n");
}

TEST(ReplaySummary, RateIsZeroWhenNoTimePassed) {
  ogf::replay::ReplayCounts counts;
  counts.data = 4;
  EXPECT_EQ(ogf::replay::summaryLine(counts, 1, 0.0),
            "packets 4 data 4 position 0 other 0 skipped 0 send_errors 0 poses 0 loops 1 seconds 0.000 rate 0.0\n");
}

TEST(ReplaySummary, ClockReasonNamesTheFlagWhenTheClockWasChosen) {
  const ogf::replay::GpsTimeProbe none;
  EXPECT_EQ(ogf::replay::odometryClockReason(OdometryClock::kCapture, "c.pcap", none), "--odometry-clock capture");
  EXPECT_EQ(ogf::replay::odometryClockReason(OdometryClock::kHost, "c.pcap", none), "--odometry-clock host");
}

TEST(ReplaySummary, AutoClockReasonSaysHowManyPositionPacketsShowedNoGpsTime) {
  ogf::replay::GpsTimeProbe probe;
  const std::uint8_t not_a_position_packet[3] = {1, 2, 3};
  probe.addPositionPayload(not_a_position_packet);  // malformed: not counted
  EXPECT_EQ(ogf::replay::odometryClockReason(OdometryClock::kAuto, "c.pcap", probe),
            "--odometry-clock auto: c.pcap has no PPS-locked GPS time (0 position packets looked at), so ogf-driver "
            "stamps the replayed packets on the host clock");
}

}  // namespace
