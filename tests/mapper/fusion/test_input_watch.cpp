// InputWatch: scans without poses, poses without scans, and neither are told apart once the missing
// stream has been silent for silence_s; each state is reported once, and so is the return to normal.
#include <gtest/gtest.h>

#include <ogf/fusion/input_watch.hpp>
#include <vector>

namespace ogf::fusion {
namespace {

constexpr std::int64_t kSecondUs = 1'000'000;
constexpr std::int64_t kStart = 100 * kSecondUs;

// Feeds scans at 10 Hz and/or poses at 100 Hz from `from` to `to` (steady µs), observing every 10 ms;
// returns the changes reported.
std::vector<InputWatch::Change> run(InputWatch& w, std::int64_t from, std::int64_t to, bool scans,
                                    bool poses) {
  std::vector<InputWatch::Change> out;
  for (std::int64_t t = from; t < to; t += 10'000) {
    if (scans && (t - from) % 100'000 == 0) w.scanArrived(t);
    if (poses) w.poseArrived(t);
    if (auto c = w.observe(t)) out.push_back(*c);
  }
  return out;
}

TEST(InputWatch, ScansWithoutPosesAreReportedOnceAfterTheSilenceAndTheRecoveryOnce) {
  InputWatch w(InputWatchConfig{}, kStart);
  auto changes = run(w, kStart, kStart + 2 * kSecondUs, true, false);
  EXPECT_TRUE(changes.empty()) << "within the silence the poses may still come";
  EXPECT_EQ(w.state(), InputState::kNone);
  changes = run(w, kStart + 2 * kSecondUs, kStart + 10 * kSecondUs, true, false);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kWaitingForPoses);
  EXPECT_EQ(changes[0].previous, InputState::kNone);
  EXPECT_GT(w.silentFor(kStart + 10 * kSecondUs), 3 * kSecondUs);
  changes = run(w, kStart + 10 * kSecondUs, kStart + 12 * kSecondUs, true, true);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kOk);
  EXPECT_EQ(changes[0].previous, InputState::kWaitingForPoses);
}

TEST(InputWatch, PosesWithoutScansAreWaitingForScansAndBothStoppedIsNoInput) {
  InputWatch w(InputWatchConfig{}, kStart);
  auto changes = run(w, kStart, kStart + 2 * kSecondUs, true, true);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kOk);
  changes = run(w, kStart + 2 * kSecondUs, kStart + 8 * kSecondUs, false, true);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kWaitingForScans);
  EXPECT_EQ(*w.sinceScan(kStart + 8 * kSecondUs), 8 * kSecondUs - (2 * kSecondUs - 100'000));
  changes = run(w, kStart + 8 * kSecondUs, kStart + 14 * kSecondUs, false, false);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kNone);
  EXPECT_EQ(w.state(), InputState::kNone);
}

TEST(InputWatch, BothStoppingAMomentApartIsNoInputNotAMissingPose) {
  // A replay ends: the poses stop, the driver's last scan follows 0.8 s later.
  InputWatch w(InputWatchConfig{}, kStart);
  auto changes = run(w, kStart, kStart + 5 * kSecondUs, true, true);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kOk);
  changes = run(w, kStart + 5 * kSecondUs, kStart + 5 * kSecondUs + 900'000, true, false);
  const auto rest = run(w, kStart + 5 * kSecondUs + 900'000, kStart + 12 * kSecondUs, false, false);
  changes.insert(changes.end(), rest.begin(), rest.end());
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kNone);
  EXPECT_EQ(changes[0].previous, InputState::kOk);
}

TEST(InputWatch, AScanStreamThatNeverCameIsMissingEvenWhenThePosesStopSoonAfter) {
  // Poses for 2 s, then none; no scan ever: the scans are what is missing, from the end of the grace on.
  InputWatch w(InputWatchConfig{}, kStart);
  auto changes = run(w, kStart, kStart + 2 * kSecondUs, false, true);
  const auto rest = run(w, kStart + 2 * kSecondUs, kStart + 4 * kSecondUs, false, false);
  changes.insert(changes.end(), rest.begin(), rest.end());
  ASSERT_FALSE(changes.empty());
  EXPECT_EQ(changes[0].state, InputState::kWaitingForScans);
}

TEST(InputWatch, NothingAtAllIsReportedOnceWhenTheStartsGraceEnds) {
  InputWatch w(InputWatchConfig{}, kStart);
  const auto changes = run(w, kStart, kStart + 20 * kSecondUs, false, false);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kNone);
  EXPECT_EQ(changes[0].previous, InputState::kNone);
  EXPECT_FALSE(w.sinceScan(kStart + 20 * kSecondUs).has_value());
  EXPECT_FALSE(w.sincePose(kStart + 20 * kSecondUs).has_value());
}

TEST(InputWatch, WithAFixedPoseScansAloneAreOkAndTheirAbsenceIsWaitingForScans) {
  InputWatch w(InputWatchConfig{3.0, false}, kStart);
  auto changes = run(w, kStart, kStart + 5 * kSecondUs, true, false);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kOk);
  changes = run(w, kStart + 5 * kSecondUs, kStart + 10 * kSecondUs, false, true);
  ASSERT_EQ(changes.size(), 1U);
  EXPECT_EQ(changes[0].state, InputState::kWaitingForScans) << "poses are not an input with a fixed pose";
}

}  // namespace
}  // namespace ogf::fusion
