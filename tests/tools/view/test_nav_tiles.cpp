// The navigation grid on its way to the page: a nav frame carries tiles byte for byte and refuses bytes
// that are not one; the view's copy of the grid sends the tiles a keyframe or an update changed and no
// others, a tile that became unknown as unknown, and at most its bound of tiles; a tick of the feed carries
// the changed tiles and a browser that joins gets every tile.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "ogf/navigation/nav_stream.hpp"
#include "ogf/view/feed_state.hpp"
#include "ogf/view/nav_frame.hpp"
#include "ogf/view/nav_tiles.hpp"

namespace {

using namespace ogf::view;
using ogf::navigation::CellState;
using ogf::navigation::NavBand;
using ogf::navigation::NavProjection;
using ogf::navigation::NavReceiver;
using ogf::navigation::NavStream;
using ogf::navigation::TileKey;

constexpr double kRes = 0.2;

// A cell in the default band (0.25..1.5 m above z = 0): layer 2 at 0.2 m is centred at 0.5 m.
CellState bandCell(int x, int y, bool occupied) {
  return {{x, y, 2}, occupied ? 0.9 : 0.1,
          occupied ? ogf::navigation::kClassOccupied : ogf::navigation::kClassFree, 0.01f};
}

struct Mapper {
  NavProjection projection = std::move(NavProjection::create(kRes, NavBand{}).value());
  NavStream stream{7};
  // Every layer of the band free over x, y in [x0, x1) × [y0, y1): known free columns.
  void freeRect(int x0, int x1, int y0, int y1) {
    for (int x = x0; x < x1; ++x)
      for (int y = y0; y < y1; ++y)
        for (int z = 2; z <= 7; ++z) projection.update(CellState{{x, y, z}, 0.1, ogf::navigation::kClassFree, 0.01f});
  }
  std::vector<TileKey> refresh() { return projection.refresh(); }
};

void feed(NavReceiver& r, const std::vector<ogf::nav_grid_t>& msgs) {
  for (const auto& m : msgs) r.accept(m);
}

std::vector<TileKey> keysOf(const std::vector<NavTile>& tiles) {
  std::vector<TileKey> out;
  for (const auto& t : tiles) out.push_back(t.key);
  return out;
}

TEST(NavFrame, RoundTripKeepsTilesValuesAndHeader) {
  std::vector<NavTile> tiles(3);
  std::mt19937 rng(3);
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    tiles[i].key = {static_cast<int>(i) - 1, 5};
    tiles[i].cost.resize(kNavTileColumns);
    tiles[i].column_class.resize(kNavTileColumns);
    for (std::size_t j = 0; j < kNavTileColumns; ++j) {
      tiles[i].cost[j] = static_cast<std::int8_t>(rng() % 101);
      tiles[i].column_class[j] = static_cast<std::int8_t>(static_cast<int>(rng() % 3) - 1);
    }
  }
  const auto frames = encodeNavFrames(tiles, true, 0.2, -1.5, 2);
  ASSERT_EQ(frames.size(), 2u);
  std::vector<NavTile> back;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(frames[f].size() % 4, 0u);
    const auto d = decodeNavFrame(frames[f]);
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(d->full, f == 0);
    EXPECT_FLOAT_EQ(d->resolution, 0.2f);
    EXPECT_FLOAT_EQ(d->floor_z, -1.5f);
    back.insert(back.end(), d->tiles.begin(), d->tiles.end());
  }
  ASSERT_EQ(back.size(), tiles.size());
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    EXPECT_EQ(back[i].key, tiles[i].key);
    EXPECT_EQ(back[i].cost, tiles[i].cost);
    EXPECT_EQ(back[i].column_class, tiles[i].column_class);
  }
}

TEST(NavFrame, AFullFrameOfNoTileStillGoesOutAndBadBytesAreRefused) {
  const auto frames = encodeNavFrames({}, true, 0.2, 0.0);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].size(), kNavFrameHeaderBytes);
  EXPECT_TRUE(decodeNavFrame(frames[0]).has_value());
  EXPECT_TRUE(encodeNavFrames({}, false, 0.2, 0.0).empty());
  auto bytes = frames[0];
  bytes[0] ^= 1;
  EXPECT_FALSE(decodeNavFrame(bytes).has_value());
  bytes = frames[0];
  bytes[8] = 1;  // claims a tile it does not carry
  EXPECT_FALSE(decodeNavFrame(bytes).has_value());
}

TEST(NavTiles, FollowSendsTheTilesAKeyframeOrUpdateChangedAndNoOthers) {
  Mapper m;
  m.freeRect(0, 64, 0, 32);  // tiles (0,0) and (1,0)
  m.refresh();
  NavReceiver r;
  feed(r, m.stream.keyframe(1, m.projection));
  NavTiles tiles;
  const auto first = tiles.follow(r);
  EXPECT_EQ(keysOf(first), (std::vector<TileKey>{{0, 0}, {1, 0}}));
  EXPECT_TRUE(tiles.follow(r).empty()) << "nothing changed";

  m.projection.update(bandCell(40, 3, true));  // tile (1,0) only
  feed(r, m.stream.update(2, m.projection, m.refresh()));
  const auto second = tiles.follow(r);
  ASSERT_EQ(keysOf(second), (std::vector<TileKey>{{1, 0}}));
  EXPECT_EQ(second[0].column_class[3 * 32 + 8], ogf::navigation::kClassOccupied);

  // A keyframe of the same grid changes nothing the page has.
  feed(r, m.stream.keyframe(3, m.projection));
  EXPECT_TRUE(tiles.follow(r).empty());
  EXPECT_EQ(tiles.size(), 2u);
}

TEST(NavTiles, ATileThatBecameUnknownIsSentAsUnknownAndDropped) {
  Mapper m;
  m.freeRect(0, 64, 0, 32);
  m.refresh();
  NavReceiver r;
  feed(r, m.stream.keyframe(1, m.projection));
  NavTiles tiles;
  tiles.follow(r);
  // A new map of tile (0,0) alone.
  Mapper other;
  other.stream.reset(8);
  other.freeRect(0, 32, 0, 32);
  other.refresh();
  feed(r, other.stream.keyframe(1, other.projection));
  const auto changed = tiles.follow(r);
  ASSERT_EQ(keysOf(changed), (std::vector<TileKey>{{1, 0}}));
  EXPECT_TRUE(std::all_of(changed[0].column_class.begin(), changed[0].column_class.end(),
                          [](std::int8_t c) { return c == ogf::navigation::kClassUnknown; }));
  EXPECT_EQ(tiles.size(), 1u);
}

TEST(NavTiles, AtMostTheBoundOfTilesIsKeptAndTheRestCounted) {
  Mapper m;
  m.freeRect(0, 160, 0, 32);  // five tiles
  m.refresh();
  NavReceiver r;
  feed(r, m.stream.keyframe(1, m.projection));
  NavTiles tiles(3);
  EXPECT_EQ(tiles.follow(r).size(), 3u);
  EXPECT_EQ(tiles.size(), 3u);
  EXPECT_EQ(tiles.notDrawn(), 2u);
}

std::size_t navTilesIn(const std::vector<Frame>& frames, bool* full = nullptr) {
  std::size_t n = 0;
  for (const auto& f : frames) {
    if (!f.binary) continue;
    const auto d = decodeNavFrame({reinterpret_cast<const std::uint8_t*>(f.bytes->data()), f.bytes->size()});
    if (!d) continue;
    if (full != nullptr) *full = d->full;
    n += d->tiles.size();
  }
  return n;
}

TEST(FeedState, TickCarriesChangedNavTilesAndAJoiningBrowserGetsEveryTile) {
  FeedState state(true);
  Mapper m;
  m.freeRect(0, 64, 0, 64);  // four tiles
  m.refresh();
  feed(state.navReceiver(), m.stream.keyframe(1, m.projection));
  EXPECT_EQ(navTilesIn(state.takeUpdate()), 4u);
  EXPECT_EQ(navTilesIn(state.takeUpdate()), 0u) << "a tick without change sends no tile";

  m.projection.update(bandCell(1, 1, true));
  feed(state.navReceiver(), m.stream.update(2, m.projection, m.refresh()));
  const auto update = state.takeUpdate();
  EXPECT_EQ(navTilesIn(update), 1u);
  EXPECT_NE(update.back().bytes->find(R"("nav":{"seq":1,"known_columns":4096)"), std::string::npos)
      << *update.back().bytes;

  bool full = false;
  EXPECT_EQ(navTilesIn(state.wholeState(), &full), 4u);
  EXPECT_TRUE(full);
}

TEST(FeedState, NavMessagesThatDoNotDecodeAreCountedWithTheMalformed) {
  FeedState state(true);
  state.countNavMessage(false);
  ogf::nav_grid_t bad{};
  bad.tile_size = 16;
  state.countNavMessage(true);
  state.navReceiver().accept(bad);
  const auto update = state.takeUpdate();
  EXPECT_EQ(state.nav().malformed, 2u);
  EXPECT_EQ(state.nav().messages, 2u);
  EXPECT_NE(update.back().bytes->find(R"("malformed":2,"messages":2)"), std::string::npos) << *update.back().bytes;
}

TEST(FeedState, ASavedMapHasNoNavFigures) {
  FeedState state(false);
  EXPECT_NE(state.takeUpdate().back().bytes->find(R"("nav":null)"), std::string::npos);
}

}  // namespace
