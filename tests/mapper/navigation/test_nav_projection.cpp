#include <gtest/gtest.h>

#include <random>

#include "ogf/navigation/nav_projection.hpp"

namespace ogf::navigation {
namespace {

constexpr double kRes = 0.2;  // band layers 1..7 with the default band

NavProjection make(NavBand band = {}) {
  auto p = NavProjection::create(kRes, band);
  EXPECT_TRUE(p.ok());
  return std::move(*p);
}

CellState freeCell(CellKey k) { return {k, 0.1, kClassFree, 0.0f}; }
CellState wallCell(CellKey k) { return {k, 0.9, kClassOccupied, 0.0f}; }

TEST(NavProjection, RefusesABandWithoutLayers) {
  NavBand band;
  band.max_height = band.min_height;
  EXPECT_FALSE(NavProjection::create(kRes, band).ok());
}

TEST(NavProjection, AWallInTheBandIsOccupiedTheFloorBelowItIsNot) {
  auto p = make();
  // Column (3, 4): the floor (layer 0) occupied, free above it: free, not blocked by its own floor.
  p.update(wallCell({3, 4, 0}));
  for (int z = 1; z <= 7; ++z) p.update(freeCell({3, 4, z}));
  // Column (5, 4): a wall at layer 3.
  p.update(wallCell({5, 4, 3}));
  // Column (7, 4): a ceiling above the band (layer 12) and free cells in it.
  p.update(wallCell({7, 4, 12}));
  for (int z = 1; z <= 4; ++z) p.update(freeCell({7, 4, z}));
  const auto changed = p.refresh();
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], (TileKey{0, 0}));
  EXPECT_EQ(p.column({3, 4}), (NavColumn{10, kClassFree}));
  EXPECT_EQ(p.column({5, 4}), (NavColumn{90, kClassOccupied}));
  EXPECT_EQ(p.column({7, 4}), (NavColumn{10, kClassFree}));  // 4 of 7 layers free: half, rounded up
  EXPECT_EQ(p.column({9, 9}), NavColumn{});
  EXPECT_EQ(p.knownColumns(), 3u);
  // Nothing changed since: no tile to send.
  p.update(freeCell({3, 4, 2}));
  EXPECT_TRUE(p.refresh().empty());
}

TEST(NavProjection, TooFewFreeLayersLeaveAColumnUnknown) {
  auto p = make();
  for (int z = 1; z <= 3; ++z) p.update(freeCell({0, 0, z}));
  p.refresh();
  EXPECT_EQ(p.column({0, 0}), NavColumn{});
  p.update(freeCell({0, 0, 4}));
  EXPECT_EQ(p.refresh().size(), 1u);
  EXPECT_EQ(p.column({0, 0}).column_class, kClassFree);
}

TEST(NavProjection, NegativeKeysFallInTilesBelowZero) {
  auto p = make();
  p.update(wallCell({-1, -33, 2}));
  const auto changed = p.refresh();
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], (TileKey{-1, -2}));
  EXPECT_EQ(tileOf({-32, -32}), (TileKey{-1, -1}));
  EXPECT_EQ(tileOf({-33, 31}), (TileKey{-2, 0}));
  EXPECT_EQ(tileOf({32, 0}), (TileKey{1, 0}));
  std::vector<std::int8_t> cost(kTileSize * kTileSize), cls(kTileSize * kTileSize);
  p.tileValues({-1, -2}, cost, cls);
  // Column (-1, -33) in tile (-1, -2): x slot 31, y slot -33 + 64 = 31.
  EXPECT_EQ(cls[31 * kTileSize + 31], kClassOccupied);
  EXPECT_EQ(cost[31 * kTileSize + 31], 90);
  EXPECT_EQ(cls[0], kClassUnknown);
}

TEST(NavProjection, TheGridIsTheRectangleOfKnownColumnsRowZeroSouth) {
  auto p = make();
  p.update(wallCell({-2, 5, 3}));
  p.update(wallCell({4, 9, 3}));
  p.refresh();
  const auto dense = p.grid();
  ASSERT_TRUE(dense) << dense.error().message;
  const NavGrid& g = *dense;
  EXPECT_EQ(g.origin, (ColumnKey{-2, 5}));
  EXPECT_EQ(g.width, 7);
  EXPECT_EQ(g.height, 5);
  EXPECT_EQ(g.column_class[g.index(0, 0)], kClassOccupied);
  EXPECT_EQ(g.column_class[g.index(6, 4)], kClassOccupied);
  EXPECT_EQ(g.column_class[g.index(6, 0)], kClassUnknown);
  EXPECT_EQ(g.at({4, 9}).cost, 90);
  EXPECT_DOUBLE_EQ(g.originX(), -0.4);
  EXPECT_DOUBLE_EQ(g.originY(), 1.0);
  EXPECT_EQ(g.knownColumns(), 2u);
  EXPECT_EQ(g.checksum(), p.checksum());
  p.clear();
  ASSERT_TRUE(p.grid());
  EXPECT_EQ(p.grid()->width, 0);
  EXPECT_EQ(p.checksum(), 0u);
}

// Known columns too far apart for one dense rectangle (more than kMaxDenseColumns): a resource error that
// says how far they spread, not an allocation; the projection keeps working and a grid small again is given.
TEST(NavProjection, ColumnsTooFarApartForADenseGridAreAResourceErrorNotAnAllocation) {
  auto p = make();
  p.update(wallCell({-70000, 0, 3}));
  p.update(wallCell({70000, 5000, 3}));
  p.refresh();
  EXPECT_EQ(p.knownColumns(), 2u);
  const auto far = p.grid();
  ASSERT_FALSE(far);
  EXPECT_EQ(far.error().kind, ogf::ErrorKind::resource);
  EXPECT_NE(far.error().message.find("140001 × 5001 columns"), std::string::npos) << far.error().message;
  // One column over the bound (2^14 + 1 by 2^14), then a wide grid well within it (4096 by 4096).
  p.clear();
  p.update(wallCell({0, 0, 3}));
  p.update(wallCell({16384, 16383, 3}));
  p.refresh();
  EXPECT_FALSE(p.grid());
  p.clear();
  p.update(wallCell({0, 0, 3}));
  p.update(wallCell({4095, 4095, 3}));
  p.refresh();
  const auto wide = p.grid();
  ASSERT_TRUE(wide) << wide.error().message;
  EXPECT_EQ(wide->width, 4096);
  EXPECT_EQ(wide->knownColumns(), 2u);
  EXPECT_EQ(wide->checksum(), p.checksum());
}

// The checksum kept per change equals the one computed over the whole grid, whatever the order of changes.
TEST(NavProjection, TheRunningChecksumEqualsTheGridsAfterRandomUpdates) {
  auto p = make();
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> xy(-40, 40), z(-1, 9), cls(-1, 1);
  std::uniform_real_distribution<double> prob(0.0, 1.0);
  for (int round = 0; round < 20; ++round) {
    for (int i = 0; i < 500; ++i)
      p.update({{xy(rng), xy(rng), z(rng)}, prob(rng), static_cast<std::int8_t>(cls(rng)), 0.2f});
    p.refresh();
    const auto g = p.grid();
    ASSERT_TRUE(g) << round;
    ASSERT_EQ(p.checksum(), g->checksum()) << round;
    ASSERT_EQ(p.knownColumns(), g->knownColumns()) << round;
  }
  EXPECT_GT(p.knownColumns(), 100u);
}

}  // namespace
}  // namespace ogf::navigation
