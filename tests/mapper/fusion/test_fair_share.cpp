// FairShare: oldest-first while the sources take alike, and a source that takes more than its share served
// only with the time the others leave.
#include "ogf/fusion/fair_share.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace {

using ogf::fusion::FairShare;
using Candidate = FairShare::Candidate;

constexpr std::int64_t kSlack = 100'000;
constexpr std::int64_t kWindow = 1'000'000;

TEST(FairShare, NothingReadyNothingChosen) {
  const FairShare share(2, kSlack, kWindow);
  EXPECT_FALSE(share.choose({}).has_value());
}

TEST(FairShare, SourcesThatTakeAlikeAreServedOldestFirst) {
  FairShare share(2, kSlack, kWindow);
  const std::vector<Candidate> ready{{0, 2'000}, {1, 1'000}};
  EXPECT_EQ(share.choose(ready), 1u);
  share.served(1, 20'000);
  share.served(0, 25'000);
  EXPECT_EQ(share.choose(ready), 1u) << "within the slack of each other, the older scan goes first";
}

TEST(FairShare, AFloodDatedInThePastDoesNotStarveTheOtherSource) {
  // Source 1 sends scans that take 300 ms each and are dated 8 s before source 0's (20 ms each), and always
  // has one ready. Source 0's scans come every 100 ms: every one of them is mapped as soon as the scan in
  // hand is done, and source 1 gets the rest.
  FairShare share(2, kSlack, kWindow);
  std::int64_t now = 0, mapped_real = 0, mapped_flood = 0, real_due = 0, real_waiting = 0, most_waiting = 0,
               real_sent = 0;
  while (now < 10'000'000) {
    while (real_due <= now) {
      ++real_waiting;
      ++real_sent;
      real_due += 100'000;
    }
    most_waiting = std::max(most_waiting, real_waiting);
    std::vector<Candidate> ready{{1, now - 8'000'000}};
    if (real_waiting > 0) ready.push_back({0, now - 50'000});
    const auto chosen = share.choose(ready);
    ASSERT_TRUE(chosen.has_value());
    if (ready[*chosen].source == 0) {
      --real_waiting;
      ++mapped_real;
      share.served(0, 20'000);
      now += 20'000;
    } else {
      ++mapped_flood;
      share.served(1, 300'000);
      now += 300'000;
    }
  }
  EXPECT_GE(real_sent, 98) << "source 0 sends a scan every 100 ms for 10 s";
  EXPECT_EQ(mapped_real + real_waiting, real_sent);
  EXPECT_LE(real_waiting, 4) << "what is left of them arrived during the last of the flood's scans";
  EXPECT_LE(most_waiting, 4) << "source 0 never waits for more than one of the flood's scans";
  EXPECT_GT(mapped_flood, 20) << "the flood still gets the time source 0 leaves";
}

TEST(FairShare, ASilentSourceBanksAtMostTheWindow) {
  FairShare share(2, kSlack, kWindow);
  share.served(0, 60'000'000);  // source 1 silent for a minute of the worker's time
  EXPECT_EQ(share.servedUs(1), 60'000'000 - kWindow);
  const std::vector<Candidate> ready{{0, 1'000}, {1, 2'000}};
  EXPECT_EQ(share.choose(ready), 1u) << "it is behind, so it goes first ...";
  share.served(1, kWindow - kSlack + 1);
  EXPECT_EQ(share.choose(ready), 0u) << "... but only for the window's worth, not for a minute";
}

}  // namespace
