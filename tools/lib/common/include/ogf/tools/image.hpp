// An 8-bit image in memory (grey or RGB, rows top to bottom), with the few drawing operations the tools'
// figures need: filled rectangles and straight lines.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ogf::tools {

using Rgb = std::array<std::uint8_t, 3>;

struct Image {
  int width = 0;
  int height = 0;
  int channels = 3;  // 1 grey, 3 RGB
  std::vector<std::uint8_t> pixels;

  static Image rgb(int width, int height, Rgb fill = {255, 255, 255});
  // Writes one pixel; outside the image it does nothing.
  void set(int x, int y, Rgb colour);
  Rgb at(int x, int y) const;
  void fillRect(int x0, int y0, int w, int h, Rgb colour);
  // A line from (x0, y0) to (x1, y1), `thickness` pixels wide.
  void drawLine(int x0, int y0, int x1, int y1, Rgb colour, int thickness = 1);
};

}  // namespace ogf::tools
