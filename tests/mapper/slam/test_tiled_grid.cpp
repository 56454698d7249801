// The copy-on-write tiled grid: copies share tiles, a write clones only its tile, the grid grows in every
// direction, reads never allocate.
#include <gtest/gtest.h>

#include <ogf/slam/tiled_grid.hpp>

namespace ogf::slam {
namespace {

TEST(TiledGrid, UnobservedCellsReadAsUnknownWithoutAllocating) {
  const TiledGrid g(0.05);
  EXPECT_EQ(g.occupancy({12, -7}), -1.0);
  EXPECT_EQ(g.allocatedTiles(), 0U);
}

TEST(TiledGrid, GrowsInEveryDirectionAndKeepsCells) {
  TiledGrid g(0.05);
  g.recordHit({0, 0}, 0.01, 0.02);
  g.recordVisit({-1000, 5});
  g.recordVisit({700, -900});
  g.recordHit({0, 0}, 0.03, 0.04);
  EXPECT_EQ(g.cell({0, 0}).hits, 2U);
  EXPECT_EQ(g.cell({0, 0}).visits, 2U);
  EXPECT_EQ(g.cell({-1000, 5}).visits, 1U);
  EXPECT_EQ(g.cell({700, -900}).visits, 1U);
  EXPECT_DOUBLE_EQ(g.occupancy({-1000, 5}), 0.0);
  EXPECT_EQ(g.allocatedTiles(), 3U);
  const Eigen::Vector2d mean = g.meanEndpoint({0, 0});
  EXPECT_NEAR(mean.x(), 0.02, 1e-6);
  EXPECT_NEAR(mean.y(), 0.03, 1e-6);
}

TEST(TiledGrid, NegativeCoordinatesMapToTheirOwnCells) {
  TiledGrid g(0.1);
  EXPECT_EQ(g.cellOf(-0.05, 0.05), (CellIndex{-1, 0}));
  g.recordHit(g.cellOf(-0.05, -0.05), -0.05, -0.05);
  EXPECT_EQ(g.cell({-1, -1}).hits, 1U);
  EXPECT_EQ(g.cell({0, 0}).hits, 0U);
  EXPECT_EQ(g.cell({-1, 0}).hits, 0U);
}

TEST(TiledGrid, CopySharesEveryTileAndCopiesNoCells) {
  TiledGrid a(0.05);
  for (int x = -200; x < 200; x += 7) a.recordHit({x, x / 2}, x * 0.05, x * 0.025);
  const std::size_t tiles = a.allocatedTiles();
  ASSERT_GT(tiles, 10U);
  const TiledGrid b = a;  // what resampling does to a particle's map
  EXPECT_EQ(b.sharedTilesWith(a), tiles);
  EXPECT_EQ(a.sharedTilesWith(b), tiles);
}

TEST(TiledGrid, WriteClonesOnlyTheWrittenTileAndLeavesTheOtherCopyUnchanged) {
  TiledGrid a(0.05);
  for (int x = 0; x < 320; ++x) a.recordVisit({x, 3});  // 10 tiles in a row
  TiledGrid b = a;
  b.recordHit({5, 3}, 0.26, 0.16);
  EXPECT_EQ(b.sharedTilesWith(a), a.allocatedTiles() - 1);
  EXPECT_EQ(a.cell({5, 3}).hits, 0U);
  EXPECT_EQ(b.cell({5, 3}).hits, 1U);
  // A second write to the same tile does not clone again.
  b.recordHit({6, 3}, 0.31, 0.16);
  EXPECT_EQ(b.sharedTilesWith(a), a.allocatedTiles() - 1);
}

}  // namespace
}  // namespace ogf::slam
