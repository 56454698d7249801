#include "ogf/view/keyframe_retry.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

using ogf::view::KeyframeRetry;
using Clock = KeyframeRetry::Clock;
using std::chrono::milliseconds;
using std::chrono::seconds;

// The times of the requests a caller sends while a keyframe is needed, checking every 100 ms from t0 until
// `until`.
std::vector<Clock::duration> requestTimes(KeyframeRetry& retry, Clock::time_point t0, Clock::duration until) {
  std::vector<Clock::duration> times;
  for (Clock::duration t{}; t <= until; t += milliseconds(100)) {
    if (retry.due(t0 + t)) {
      retry.asked(t0 + t);
      times.push_back(t);
    }
  }
  return times;
}

TEST(KeyframeRetry, AStreamNotHeardIsAskedForAtDoublingIntervalsUpToTheLongest) {
  KeyframeRetry retry(seconds(1), seconds(8));
  const auto times = requestTimes(retry, Clock::now(), seconds(40));
  const std::vector<Clock::duration> expected{seconds(0), seconds(1), seconds(3), seconds(7), seconds(15),
                                              seconds(23), seconds(31), seconds(39)};
  EXPECT_EQ(times, expected);
}

TEST(KeyframeRetry, TheFirstMessageHeardMakesItDueAtOnceAndThenEveryRetry) {
  KeyframeRetry retry(seconds(1), seconds(30));
  const Clock::time_point t0 = Clock::now();
  EXPECT_EQ(requestTimes(retry, t0, seconds(5)).size(), 3u);  // at 0, 1 and 3 s; the next at 7 s
  const Clock::time_point heardAt = t0 + milliseconds(5500);
  EXPECT_FALSE(retry.due(heardAt));
  retry.heard();
  EXPECT_TRUE(retry.due(heardAt));
  retry.asked(heardAt);
  retry.heard();  // only the first message makes a request due
  EXPECT_FALSE(retry.due(heardAt + milliseconds(900)));
  EXPECT_TRUE(retry.due(heardAt + seconds(1)));
  retry.asked(heardAt + seconds(1));
  EXPECT_FALSE(retry.due(heardAt + milliseconds(1900)));
  EXPECT_TRUE(retry.due(heardAt + seconds(2)));  // no doubling once heard
}

TEST(KeyframeRetry, AStreamHeardBeforeAnyRequestIsAskedForEveryRetry) {
  KeyframeRetry retry(milliseconds(500), seconds(30));
  retry.heard();
  const auto times = requestTimes(retry, Clock::now(), seconds(2));
  const std::vector<Clock::duration> expected{milliseconds(0), milliseconds(500), milliseconds(1000),
                                              milliseconds(1500), milliseconds(2000)};
  EXPECT_EQ(times, expected);
}

TEST(KeyframeRetry, ALongestBelowTheRetryKeepsTheRetry) {
  KeyframeRetry retry(seconds(5), seconds(1));
  const auto times = requestTimes(retry, Clock::now(), seconds(12));
  const std::vector<Clock::duration> expected{seconds(0), seconds(5), seconds(10)};
  EXPECT_EQ(times, expected);
}

}  // namespace
