// What ogf-view's browsers are sent: a tick carries the cells that changed and then the figures, a tick
// without change the figures alone; a browser that joins gets every occupied box and the figures, however
// many ticks went before. The address printed at start and the token read from a file.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ogf/view/access_token.hpp"
#include "ogf/view/feed_state.hpp"
#include "ogf/view/view_address.hpp"

namespace {

using ogf::view::FeedState;
using ogf::view::Frame;

ogf::delta::PublishedCell occupied(int x) { return {{x, 0, 0}, 9000, ogf::map_delta_t::CLASS_OCCUPIED, 0.25f}; }

std::size_t binaryFrames(const std::vector<Frame>& frames) {
  std::size_t n = 0;
  for (const auto& f : frames) n += f.binary ? 1 : 0;
  return n;
}

TEST(FeedState, TickSendsChangedCellsThenFiguresAndOnlyFiguresWithoutChange) {
  FeedState feed(false);
  feed.stream().resolution = 0.2;
  feed.slots().set(occupied(1));
  const auto first = feed.takeUpdate();
  ASSERT_GE(first.size(), 2u);
  EXPECT_GE(binaryFrames(first), 1u);
  EXPECT_FALSE(first.back().binary);
  EXPECT_NE(first.back().bytes->find("\"stream\""), std::string::npos);
  const auto second = feed.takeUpdate();
  ASSERT_EQ(second.size(), 1u);
  EXPECT_FALSE(second.front().binary);
}

TEST(FeedState, JoiningBrowserGetsEveryOccupiedBoxAfterTicksHaveSentThem) {
  FeedState feed(false);
  feed.stream().resolution = 0.2;
  feed.slots().set(occupied(1));
  feed.slots().set(occupied(2));
  (void)feed.takeUpdate();
  (void)feed.takeUpdate();
  const auto whole = feed.wholeState();
  EXPECT_GE(binaryFrames(whole), 1u);
  EXPECT_FALSE(whole.back().binary);
  EXPECT_EQ(feed.stream().occupied, 2u);
}

TEST(ViewAddress, WildcardShowsLoopbackIpv6GetsBracketsAndTheTokenGoesWhereItCameFrom) {
  EXPECT_EQ(ogf::view::addressLine("127.0.0.1", 8765, "", ""), "ogf-view: http://127.0.0.1:8765/\n");
  EXPECT_EQ(ogf::view::addressLine("0.0.0.0", 80, "abc", ""), "ogf-view: http://127.0.0.1:80/?token=abc\n");
  EXPECT_EQ(ogf::view::addressLine("::1", 80, "abc", "/etc/t"),
            "ogf-view: http://[::1]:80/ (add ?token= and the token in /etc/t)\n");
}

TEST(ViewAddress, TokenFileGivesItsFirstLineWithoutSurroundingBlanks) {
  EXPECT_EQ(ogf::view::tokenOfFileText(" \tabcdef0123456789\r\nsecond line\n"), "abcdef0123456789");
  EXPECT_EQ(ogf::view::tokenOfFileText("only"), "only");
  EXPECT_EQ(ogf::view::tokenOfFileText(""), "");
}

}  // namespace
