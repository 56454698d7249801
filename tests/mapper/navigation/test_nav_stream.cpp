#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "ogf/navigation/nav_receiver.hpp"
#include "ogf/navigation/nav_stream.hpp"

namespace ogf::navigation {
namespace {

constexpr double kStreamRes = 0.1;

class NavStreamTest : public ::testing::Test {
 protected:
  NavStreamTest() : projection_(std::move(NavProjection::create(kStreamRes, NavBand{}).value())) {}

  // Random cells over `spread` columns each side of the origin, then the tiles that changed.
  std::vector<TileKey> scan(int cells = 2000, int spread = 100) {
    std::uniform_int_distribution<int> xy(-spread, spread), z(2, 14), cls(-1, 1);
    std::uniform_real_distribution<double> prob(0.0, 1.0);
    for (int i = 0; i < cells; ++i)
      projection_.update({{xy(rng_), xy(rng_), z(rng_)}, prob(rng_), static_cast<std::int8_t>(cls(rng_)), 0.1f});
    return projection_.refresh();
  }

  std::mt19937 rng_{11};
  NavProjection projection_;
  NavStream stream_{42};
  NavReceiver receiver_;
};

TEST_F(NavStreamTest, AKeyframeThenUpdatesRebuildTheGridToTheMappersChecksum) {
  scan();
  EXPECT_TRUE(receiver_.needsKeyframe());
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  EXPECT_FALSE(receiver_.needsKeyframe());
  EXPECT_TRUE(receiver_.consistent());
  for (int i = 0; i < 10; ++i) {
    const auto tiles = scan();
    const auto msgs = stream_.update(2 + i, projection_, tiles);
    for (const auto& m : msgs) receiver_.accept(m);
  }
  EXPECT_EQ(receiver_.appliedSeq(), 10);
  EXPECT_TRUE(receiver_.consistent());
  EXPECT_EQ(receiver_.checksum(), projection_.checksum());
  const auto mineOr = projection_.grid();
  const auto theirsOr = receiver_.grid();
  ASSERT_TRUE(mineOr && theirsOr);
  const NavGrid& mine = *mineOr;
  const NavGrid& theirs = *theirsOr;
  EXPECT_EQ(theirs.origin, mine.origin);
  EXPECT_EQ(theirs.width, mine.width);
  EXPECT_EQ(theirs.cost, mine.cost);
  EXPECT_EQ(theirs.column_class, mine.column_class);
  EXPECT_DOUBLE_EQ(theirs.resolution, kStreamRes);
  EXPECT_DOUBLE_EQ(theirs.band.max_height, NavBand{}.max_height);
}

// A viewer reads the receiver tile by tile: the tiles it holds are the mapper's known tiles, each with the
// mapper's values, and a tile it does not hold reads unknown.
TEST_F(NavStreamTest, TheReceiversTilesAreTheMappersKnownTilesWithTheirValues) {
  scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  const auto tiles = receiver_.knownTiles();
  ASSERT_FALSE(tiles.empty());
  EXPECT_EQ(tiles, projection_.knownTiles());
  constexpr std::size_t kColumns = static_cast<std::size_t>(kTileSize) * kTileSize;
  std::vector<std::int8_t> cost(kColumns), cls(kColumns), want_cost(kColumns), want_cls(kColumns);
  for (const auto& t : tiles) {
    receiver_.tileValues(t, cost, cls);
    projection_.tileValues(t, want_cost, want_cls);
    EXPECT_EQ(cost, want_cost);
    EXPECT_EQ(cls, want_cls);
  }
  receiver_.tileValues({1000, 1000}, cost, cls);
  EXPECT_TRUE(std::all_of(cost.begin(), cost.end(), [](std::int8_t c) { return c == kUnknownCost; }));
  EXPECT_TRUE(std::all_of(cls.begin(), cls.end(), [](std::int8_t c) { return c == kClassUnknown; }));
}

TEST_F(NavStreamTest, EveryMessageFitsOneDatagram) {
  const auto tiles = scan(60000, 400);
  const auto msgs = stream_.update(1, projection_, tiles);
  ASSERT_GT(msgs.size(), 1u);
  for (const auto& m : msgs) {
    EXPECT_LT(m.getEncodedSize(), 65000);
    EXPECT_EQ(m.part_count, static_cast<std::int32_t>(msgs.size()));
  }
}

TEST_F(NavStreamTest, ALostUpdateIsAGapAndTheNextKeyframeRepairsIt) {
  scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  stream_.update(2, projection_, scan());  // lost
  NavReceiver::Outcome last{};
  for (const auto& m : stream_.update(3, projection_, scan())) last = receiver_.accept(m);
  EXPECT_EQ(last, NavReceiver::Outcome::kGap);
  EXPECT_TRUE(receiver_.needsKeyframe());
  EXPECT_EQ(receiver_.gaps(), 1u);
  for (const auto& m : stream_.keyframe(4, projection_)) last = receiver_.accept(m);
  EXPECT_EQ(last, NavReceiver::Outcome::kKeyframeApplied);
  EXPECT_TRUE(receiver_.consistent());
}

TEST_F(NavStreamTest, PartsInAnyOrderAssembleAndDuplicatesAreIgnored) {
  scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  auto msgs = stream_.update(2, projection_, scan(60000, 400));
  ASSERT_GT(msgs.size(), 2u);
  std::reverse(msgs.begin(), msgs.end());
  receiver_.accept(msgs.front());
  for (const auto& m : msgs) receiver_.accept(m);
  EXPECT_EQ(receiver_.appliedSeq(), 1);
  EXPECT_TRUE(receiver_.consistent());
}

TEST_F(NavStreamTest, ANewMapIdNeedsAKeyframe) {
  scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  stream_.reset(43);
  projection_.clear();
  for (const auto& m : stream_.update(2, projection_, scan())) receiver_.accept(m);
  EXPECT_TRUE(receiver_.needsKeyframe());
  for (const auto& m : stream_.keyframe(3, projection_)) receiver_.accept(m);
  EXPECT_EQ(receiver_.mapId(), 43);
  EXPECT_TRUE(receiver_.consistent());
}

TEST_F(NavStreamTest, MalformedMessagesAreCountedAndChangeNothing) {
  const auto tiles = scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  const auto before = receiver_.checksum();
  const auto good = stream_.update(2, projection_, tiles).front();
  std::vector<ogf::nav_grid_t> bad(7, good);
  bad[0].tile_size = 16;
  bad[1].num_columns -= 1;
  bad[2].cost.pop_back();
  bad[3].column_class[0] = 5;
  bad[4].cost[0] = -1;  // a known class with the unknown cost
  bad[4].column_class[0] = ogf::nav_grid_t::CLASS_FREE;
  bad[5].part_index = bad[5].part_count;
  bad[6].resolution = std::numeric_limits<double>::quiet_NaN();
  for (const auto& m : bad) EXPECT_EQ(receiver_.accept(m), NavReceiver::Outcome::kMalformed);
  EXPECT_EQ(receiver_.malformed(), bad.size());
  EXPECT_EQ(receiver_.checksum(), before);
  EXPECT_EQ(receiver_.appliedSeq(), 0);
}

TEST_F(NavStreamTest, AnUpdateWithNoTileStillCarriesItsNumber) {
  scan();
  for (const auto& m : stream_.keyframe(1, projection_)) receiver_.accept(m);
  const auto msgs = stream_.update(2, projection_, {});
  ASSERT_EQ(msgs.size(), 1u);
  EXPECT_EQ(msgs[0].num_tiles, 0);
  EXPECT_EQ(receiver_.accept(msgs[0]), NavReceiver::Outcome::kApplied);
  EXPECT_EQ(receiver_.appliedSeq(), 1);
}

}  // namespace
}  // namespace ogf::navigation
