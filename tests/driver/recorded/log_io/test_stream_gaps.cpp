// StreamGaps: exact counts from sequence numbers, estimates from silences, nothing on a steady stream.
#include <gtest/gtest.h>

#include "ogf/log_io/stream_gaps.hpp"

namespace {

using ogf::log_io::StreamGaps;

TEST(StreamGaps, SteadyStreamHasNone) {
  StreamGaps g;
  for (int i = 0; i < 100; ++i) g.add(i * 100'000, i);
  EXPECT_EQ(g.gaps(), 0);
  EXPECT_EQ(g.missing(), 0);
  EXPECT_EQ(g.summary("x"), "");
}

TEST(StreamGaps, SequenceGapsAreExact) {
  StreamGaps g;
  for (int i = 0; i < 201; ++i)
    if (i < 3 || i > 197) g.add(i * 100'000, i);
  EXPECT_EQ(g.messages(), 6);
  EXPECT_EQ(g.missing(), 195);
  EXPECT_EQ(g.gaps(), 1);
  EXPECT_EQ(g.summary("VELODYNE_SCAN"), "VELODYNE_SCAN: 195 missing in 1 gap (the longest 19.600 s): 6 of 201 recorded");
}

TEST(StreamGaps, SilencesWithoutSequenceAreEstimated) {
  StreamGaps g;
  std::int64_t t = 0;
  for (int i = 0; i < 10; ++i) g.add(t += 100'000);
  g.add(t += 1'000'000);  // 9 batches of 100 ms missing
  for (int i = 0; i < 10; ++i) g.add(t += 100'000);
  EXPECT_EQ(g.gaps(), 1);
  EXPECT_EQ(g.missing(), 9);
  EXPECT_EQ(g.longestGapUs(), 1'000'000);
}

TEST(StreamGaps, JitterIsNoGap) {
  StreamGaps g;
  std::int64_t t = 0;
  for (int i = 0; i < 50; ++i) g.add(t += (i % 2 ? 60'000 : 140'000));
  EXPECT_EQ(g.gaps(), 0);
}

TEST(StreamGaps, ARestartedSequenceIsNoGap) {
  StreamGaps g;
  for (int i = 0; i < 5; ++i) g.add(i * 100'000, 100 + i);
  for (int i = 0; i < 5; ++i) g.add(600'000 + i * 100'000, i);
  EXPECT_EQ(g.gaps(), 0);
}

}  // namespace
