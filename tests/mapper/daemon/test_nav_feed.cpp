// The live navigation grid's publishing rule (mapper_daemon/nav_feed.hpp): when updates and keyframes go
// out, what they carry, and that a client following them (navigation::NavReceiver) ends with the grid.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "ogf/mapper_daemon/nav_feed.hpp"
#include "ogf/navigation/nav_receiver.hpp"

namespace ogf::mapper_daemon {
namespace {

constexpr double kRes = 0.2;  // the default band holds layers 1..7 at 0.2 m; 4 free layers make a column free
constexpr std::int64_t kMs = 1000;
const NavFeedTiming kTiming{500 * kMs, 5000 * kMs, 1000 * kMs};

using navigation::kTileSize;

delta::PublishedCell cell(std::int32_t x, std::int32_t y, std::int32_t z, std::int8_t cls) {
  const std::int16_t p = cls > 0 ? 9000 : cls < 0 ? 1000 : 5000;
  return {{x, y, z}, p, cls, 0.05f};
}
// An occupied column: a wall cell in the band.
std::vector<delta::PublishedCell> wall(std::int32_t x, std::int32_t y) { return {cell(x, y, 3, 1)}; }
// A free column: four free cells in the band.
std::vector<delta::PublishedCell> open(std::int32_t x, std::int32_t y) {
  return {cell(x, y, 1, -1), cell(x, y, 2, -1), cell(x, y, 3, -1), cell(x, y, 4, -1)};
}

NavFeed makeFeed(std::int64_t map_id = 7) { return std::move(NavFeed::create(kRes, navigation::NavBand{}, map_id, kTiming).value()); }

std::vector<navigation::TileKey> tilesOf(const std::vector<ogf::nav_grid_t>& msgs) {
  std::vector<navigation::TileKey> out;
  for (const auto& m : msgs)
    for (std::size_t i = 0; i < m.tile_x.size(); ++i) out.push_back({m.tile_x[i], m.tile_y[i]});
  return out;
}

TEST(NavFeed, APublishedCellReadsAsItsProbabilityClassAndVariance) {
  const auto s = cellStateOf({{1, -2, 3}, 7500, 1, 0.25f});
  EXPECT_EQ(s.key, (CellKey{1, -2, 3}));
  EXPECT_DOUBLE_EQ(s.probability, 0.75);
  EXPECT_EQ(s.cell_class, 1);
  EXPECT_FLOAT_EQ(s.variance, 0.25f);
}

TEST(NavFeed, TheFirstChangesGoOutAtOnceLaterOnesWaitForTheUpdateInterval) {
  auto feed = makeFeed();
  const std::int64_t t0 = 1'000'000 * kMs;
  feed.cellsChanged(wall(0, 0), 100);
  const auto first = feed.turn(t0);
  ASSERT_FALSE(first.update.empty());
  EXPECT_EQ(first.update.front().seq, 1);
  EXPECT_EQ(first.update.front().base_seq, 0);
  EXPECT_EQ(first.update.front().utime, 100);
  EXPECT_EQ(first.update.front().map_id, 7);

  feed.cellsChanged(wall(40, 0), 200);
  EXPECT_TRUE(feed.turn(t0 + 100 * kMs).update.empty()) << "an update 0.1 s after the last one";
  EXPECT_TRUE(feed.turn(t0 + 499 * kMs).update.empty());
  EXPECT_EQ(feed.tilesWaiting(), 1u);
  const auto second = feed.turn(t0 + 500 * kMs);
  ASSERT_EQ(second.update.size(), 1u);
  EXPECT_EQ(second.update.front().seq, 2);
  EXPECT_EQ(tilesOf(second.update), (std::vector<navigation::TileKey>{{1, 0}}));
  EXPECT_EQ(second.update.front().grid_checksum, static_cast<std::int64_t>(feed.projection().checksum()));
  EXPECT_EQ(feed.tilesWaiting(), 0u);
}

TEST(NavFeed, NoUpdateGoesOutWhileNoColumnChanges) {
  auto feed = makeFeed();
  const std::int64_t t0 = 5'000 * kMs;
  feed.cellsChanged(wall(0, 0), 1);
  ASSERT_FALSE(feed.turn(t0).update.empty());
  // The same wall again, a cell below the band and one above it: no column changes.
  feed.cellsChanged(wall(0, 0), 2);
  feed.cellsChanged({{cell(5, 5, 0, 1), cell(6, 6, 9, 1)}}, 3);
  for (int i = 1; i <= 20; ++i) EXPECT_TRUE(feed.turn(t0 + i * 400 * kMs).update.empty()) << i;
  EXPECT_EQ(feed.seq(), 1);
}

TEST(NavFeed, TilesChangedByScansBetweenTwoUpdatesGoOutTogetherInTheNextOne) {
  auto feed = makeFeed();
  const std::int64_t t0 = 5'000 * kMs;
  feed.turn(t0);
  feed.cellsChanged(wall(0, 0), 1);
  ASSERT_FALSE(feed.turn(t0 + 10 * kMs).update.empty());
  feed.cellsChanged(wall(-1, 0), 2);             // tile (-1, 0)
  feed.cellsChanged(open(kTileSize * 3, 5), 3);  // tile (3, 0)
  feed.cellsChanged(wall(-1, kTileSize), 4);     // tile (-1, 1)
  EXPECT_TRUE(feed.turn(t0 + 200 * kMs).update.empty());
  const auto out = feed.turn(t0 + 600 * kMs);
  EXPECT_EQ(feed.seq(), 2);
  EXPECT_EQ(tilesOf(out.update), (std::vector<navigation::TileKey>{{-1, 0}, {-1, 1}, {3, 0}}));
  EXPECT_EQ(out.update.front().utime, 4) << "stamped with the last scan folded in";
}

TEST(NavFeed, KeyframesGoOutEveryIntervalAndAFloodOfRequestsGetsAtMostOneAGap) {
  auto feed = makeFeed();
  const std::int64_t t0 = 5'000 * kMs;
  feed.cellsChanged(wall(0, 0), 1);
  EXPECT_TRUE(feed.turn(t0).keyframe.empty()) << "the clocks start at the first turn";
  int keyframes = 0;
  // 10 s in 10 ms turns, a request at every turn from 2 s on: one asked-for keyframe a second at most.
  for (std::int64_t t = t0 + 10 * kMs; t <= t0 + 10'000 * kMs; t += 10 * kMs) {
    if (t >= t0 + 2'000 * kMs) feed.requestKeyframe();
    const auto out = feed.turn(t);
    if (out.keyframe.empty()) continue;
    ++keyframes;
    EXPECT_EQ(out.keyframe.front().kind, ogf::nav_grid_t::KIND_KEYFRAME);
    EXPECT_EQ(out.keyframe.front().base_seq, -1);
    EXPECT_EQ(out.keyframe.front().seq, feed.seq());
  }
  // Without requests: none before 5 s. With them: at 2 s and then every second until 10 s.
  EXPECT_EQ(keyframes, 9);

  auto quiet = makeFeed();
  quiet.turn(t0);
  int periodic = 0;
  for (std::int64_t t = t0 + 10 * kMs; t <= t0 + 10'000 * kMs; t += 10 * kMs) periodic += quiet.turn(t).keyframe.empty() ? 0 : 1;
  EXPECT_EQ(periodic, 2) << "every 5 s unasked";
}

TEST(NavFeed, AnUpdateDueWithAKeyframeGoesOutFirstAndTheKeyframeCarriesItsSeq) {
  auto feed = makeFeed();
  const std::int64_t t0 = 5'000 * kMs;
  feed.turn(t0);
  feed.cellsChanged(wall(0, 0), 1);
  const auto out = feed.turn(t0 + 5'000 * kMs);
  ASSERT_FALSE(out.update.empty());
  ASSERT_FALSE(out.keyframe.empty());
  EXPECT_EQ(out.update.front().seq, 1);
  EXPECT_EQ(out.keyframe.front().seq, 1);
}

TEST(NavFeed, ANewMapIsEmptyNumberedFromZeroAndItsKeyframeGoesOutAtOnce) {
  auto feed = makeFeed(7);
  const std::int64_t t0 = 5'000 * kMs;
  feed.cellsChanged(wall(0, 0), 1);
  feed.turn(t0);
  feed.cellsChanged(wall(3, 3), 2);
  feed.newMap(8);
  EXPECT_EQ(feed.projection().knownColumns(), 0u);
  EXPECT_EQ(feed.tilesWaiting(), 0u) << "the old map's changes never go out";
  const auto out = feed.turn(t0 + 10 * kMs);
  EXPECT_TRUE(out.update.empty());
  ASSERT_EQ(out.keyframe.size(), 1u);
  EXPECT_EQ(out.keyframe.front().map_id, 8);
  EXPECT_EQ(out.keyframe.front().seq, 0);
  EXPECT_EQ(out.keyframe.front().num_tiles, 0);
}

TEST(NavFeed, ARebuiltGridEqualsTheGridFedScanByScanAndLeavesNothingWaiting) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> xy(-80, 80), z(0, 9), cls(-1, 1);
  auto fed = makeFeed();
  std::map<CellKey, delta::PublishedCell> latest;
  for (int scan = 0; scan < 30; ++scan) {
    std::vector<delta::PublishedCell> changes;
    for (int i = 0; i < 500; ++i) {
      const auto c = cell(xy(rng), xy(rng), z(rng), static_cast<std::int8_t>(cls(rng)));
      changes.push_back(c);
      latest[c.key] = c;
    }
    fed.cellsChanged(changes, scan);
  }
  std::vector<delta::PublishedCell> whole;
  for (const auto& [key, c] : latest) whole.push_back(c);
  auto rebuilt = makeFeed();
  rebuilt.cellsChanged(wall(500, 500), 1);  // forgotten by the rebuild
  rebuilt.rebuild(whole);
  EXPECT_GT(rebuilt.projection().knownColumns(), 1000u);
  EXPECT_EQ(rebuilt.projection().checksum(), fed.projection().checksum());
  EXPECT_EQ(rebuilt.projection().knownColumns(), fed.projection().knownColumns());
  EXPECT_EQ(rebuilt.tilesWaiting(), 0u);
}

// A client that loses a share of the updates (and asks for a keyframe after each gap, as ogf-map-client
// does) ends with the feed's grid.
TEST(NavFeed, AReceiverLosingUpdatesRecoversByKeyframeToTheFeedsChecksum) {
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> xy(-100, 100), z(1, 7), cls(-1, 1);
  std::uniform_real_distribution<double> lose(0, 1);
  auto feed = makeFeed();
  navigation::NavReceiver receiver;
  std::int64_t t = 5'000 * kMs;
  int lost = 0;
  for (int scan = 0; scan < 200; ++scan, t += 100 * kMs) {
    std::vector<delta::PublishedCell> changes;
    for (int i = 0; i < 100; ++i) changes.push_back(cell(xy(rng), xy(rng), z(rng), static_cast<std::int8_t>(cls(rng))));
    feed.cellsChanged(changes, scan);
    if (receiver.needsKeyframe()) feed.requestKeyframe();
    const auto out = feed.turn(t);
    if (!out.update.empty() && scan < 150 && lose(rng) < 0.2) {
      ++lost;
    } else {
      for (const auto& m : out.update) receiver.accept(m);
    }
    for (const auto& m : out.keyframe) receiver.accept(m);
  }
  // Quiet at the end: a last keyframe asked for, as a client does after the drive.
  feed.requestKeyframe();
  const auto last = feed.turn(t + 2'000 * kMs);
  for (const auto& m : last.update) receiver.accept(m);
  for (const auto& m : last.keyframe) receiver.accept(m);
  EXPECT_GT(lost, 0);
  EXPECT_GT(receiver.gaps(), 0u);
  EXPECT_FALSE(receiver.needsKeyframe());
  EXPECT_EQ(receiver.appliedSeq(), feed.seq());
  EXPECT_TRUE(receiver.consistent());
  EXPECT_EQ(receiver.checksum(), feed.projection().checksum());
  EXPECT_EQ(receiver.knownColumns(), feed.projection().knownColumns());
}

}  // namespace
}  // namespace ogf::mapper_daemon
