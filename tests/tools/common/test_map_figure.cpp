// The figure layout on a small raster: scaled up by whole pixels to at least 800 pixels, every cell drawn in
// its colour and orientation (row 0 at the top), the legend's swatches and the colour bar on the page, and
// text drawn in ink. Nice steps and the sequential colours checked by hand.
#include <gtest/gtest.h>

#include <set>

#include "ogf/tools/bitmap_font.hpp"
#include "ogf/tools/map_figure.hpp"

namespace ogf::tools {
namespace {

constexpr Rgb kRed{200, 30, 30};
constexpr Rgb kBlue{30, 30, 200};
constexpr Rgb kGreen{30, 200, 30};

std::size_t countColour(const Image& img, Rgb c) {
  std::size_t n = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) n += img.at(x, y) == c ? 1U : 0U;
  }
  return n;
}

TEST(MapFigure, CellsAreScaledToAtLeast800PixelsInTheirColoursAndPlaces) {
  // 4 × 2 cells: the top row red, the bottom row blue, except the bottom-right cell green.
  MapRaster r{4, 2, {kRed, kRed, kRed, kRed, kBlue, kBlue, kBlue, kGreen}, 0.5, -1.0, 2.0};
  FigureKey key;
  key.legend = {{{1, 2, 3}, "one"}};
  const Image img = composeMapFigure(r, "title", "note", key);
  // 800 / 4 = 200 pixels per cell: the map is 800 × 400.
  EXPECT_EQ(countColour(img, kRed), 4u * 200 * 200);
  EXPECT_EQ(countColour(img, kBlue), 3u * 200 * 200);
  EXPECT_EQ(countColour(img, kGreen), 1u * 200 * 200);
  EXPECT_EQ(countColour(img, {1, 2, 3}), 22u * 22);  // the legend swatch
  EXPECT_GE(img.width, 800);
  // The green cell is the bottom right one: find its first pixel and check red lies above it.
  int gx = -1, gy = -1;
  for (int y = 0; y < img.height && gx < 0; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) == kGreen) {
        gx = x;
        gy = y;
        break;
      }
    }
  }
  ASSERT_GE(gx, 0);
  EXPECT_EQ(img.at(gx, gy - 1), kRed);
  EXPECT_EQ(img.at(gx - 1, gy), kBlue);
}

TEST(MapFigure, ALargeRasterIsNotScaledDownAndTheColourBarIsDrawn) {
  MapRaster r{1000, 10, std::vector<Rgb>(10000, kBlue), 0.1, 0.0, 0.0};
  FigureKey key;
  key.colour_bar = ColourBar{sequentialColour, "lo", "hi", "label"};
  const Image img = composeMapFigure(r, "t", "n", key);
  EXPECT_EQ(countColour(img, kBlue), 10000u);  // one pixel per cell
  EXPECT_GT(countColour(img, sequentialColour(1.0)), 20u);
  EXPECT_GT(countColour(img, sequentialColour(0.0)), 20u);
}

TEST(MapFigure, NiceStepsAndSequentialColours) {
  EXPECT_DOUBLE_EQ(niceStep(0.7), 1.0);
  EXPECT_DOUBLE_EQ(niceStep(1.3), 2.0);
  EXPECT_DOUBLE_EQ(niceStep(3.0), 5.0);
  EXPECT_DOUBLE_EQ(niceStep(5.0), 5.0);
  EXPECT_DOUBLE_EQ(niceStep(12.0), 20.0);
  EXPECT_NEAR(niceStep(0.03), 0.05, 1e-12);
  // Lightness rises from 0 to 1, and every colour differs.
  std::set<Rgb> seen;
  int lastSum = -1;
  for (int i = 0; i <= 10; ++i) {
    const Rgb c = sequentialColour(i / 10.0);
    const int sum = c[0] + c[1] + c[2];
    EXPECT_GT(sum, lastSum) << i;
    lastSum = sum;
    seen.insert(c);
  }
  EXPECT_EQ(seen.size(), 11u);
}

TEST(BitmapFont, TextIsDrawnInInkWithinItsBoxAndAMissingGlyphShowsAsABox) {
  Image img = Image::rgb(100, 40);
  drawText(img, 10, 10, "x (m)", {0, 0, 0}, 2);
  const std::size_t ink = countColour(img, {0, 0, 0});
  EXPECT_GT(ink, 40u);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      if (img.at(x, y) == Rgb{0, 0, 0}) {
        EXPECT_GE(x, 10);
        EXPECT_LT(x, 10 + textWidth("x (m)", 2));
        EXPECT_GE(y, 10);
        EXPECT_LT(y, 10 + textHeight(2));
      }
    }
  }
  Image box = Image::rgb(10, 10);
  drawText(box, 0, 0, "\x01", {0, 0, 0}, 1);
  EXPECT_EQ(countColour(box, {0, 0, 0}), 5u + 5u + 5u + 5u);  // a 5 × 7 outline: 2 × 5 + 2 × 5 pixels
}

}  // namespace
}  // namespace ogf::tools
