// A top-down map a person can read without instructions: the cell raster scaled up by whole pixels
// (nearest neighbour) until its long side reaches at least 800 pixels, framed by axes in metres with
// ticks, a title, a scale bar and either a legend of classes or a colour bar, on a white page.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ogf/tools/image.hpp"

namespace ogf::tools {

// One colour per cell column, row 0 at the top (the largest y), x to the right.
struct MapRaster {
  int width = 0;
  int height = 0;
  std::vector<Rgb> cells;  // width × height
  double resolution = 0.2;  // metres per cell
  double x0 = 0.0;          // metres: the left edge of column 0
  double y0 = 0.0;          // metres: the bottom edge of the last row
};

struct LegendEntry {
  Rgb colour;
  std::string label;
};

// A continuous key: colour(t) for t in [0, 1], labelled lo at the bottom and hi at the top.
struct ColourBar {
  std::function<Rgb(double)> colour;
  std::string lo;
  std::string hi;
  std::string label;
};

struct FigureKey {
  std::vector<LegendEntry> legend;      // drawn when not empty
  std::optional<ColourBar> colour_bar;  // drawn when set (below the legend)
};

inline constexpr int kFigureMinLongSide = 800;  // pixels of the map itself

// The whole figure. `title` goes on top, `note` (e.g. the height band) under it; each cell is at least
// `min_scale` pixels wide.
Image composeMapFigure(const MapRaster& raster, const std::string& title, const std::string& note,
                       const FigureKey& key, int min_scale = 1);

// A pleasant step for ticks and scale bars: 1, 2 or 5 × 10^k, the smallest not below `rough`.
double niceStep(double rough);

// Perceptually ordered colours for t in [0, 1]: dark blue, teal, green, yellow (for entropy, variance).
Rgb sequentialColour(double t);

}  // namespace ogf::tools
