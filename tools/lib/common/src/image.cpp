// Pixels, rectangles and Bresenham lines.
#include "ogf/tools/image.hpp"

#include <cstdlib>

namespace ogf::tools {

Image Image::rgb(int width, int height, Rgb fill) {
  Image img;
  img.width = width;
  img.height = height;
  img.channels = 3;
  img.pixels.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  for (std::size_t i = 0; i < img.pixels.size(); i += 3) {
    img.pixels[i] = fill[0];
    img.pixels[i + 1] = fill[1];
    img.pixels[i + 2] = fill[2];
  }
  return img;
}

void Image::set(int x, int y, Rgb colour) {
  if (x < 0 || y < 0 || x >= width || y >= height) {
    return;
  }
  const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                 static_cast<std::size_t>(channels);
  if (channels == 1) {
    pixels[i] = static_cast<std::uint8_t>((colour[0] + colour[1] + colour[2]) / 3);
    return;
  }
  pixels[i] = colour[0];
  pixels[i + 1] = colour[1];
  pixels[i + 2] = colour[2];
}

Rgb Image::at(int x, int y) const {
  const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) *
                 static_cast<std::size_t>(channels);
  if (channels == 1) {
    return {pixels[i], pixels[i], pixels[i]};
  }
  return {pixels[i], pixels[i + 1], pixels[i + 2]};
}

void Image::fillRect(int x0, int y0, int w, int h, Rgb colour) {
  for (int y = y0; y < y0 + h; ++y) {
    for (int x = x0; x < x0 + w; ++x) {
      set(x, y, colour);
    }
  }
}

void Image::drawLine(int x0, int y0, int x1, int y1, Rgb colour, int thickness) {
  const int dx = std::abs(x1 - x0);
  const int dy = -std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1;
  const int sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  const int half = thickness / 2;
  for (;;) {
    fillRect(x0 - half, y0 - half, thickness, thickness, colour);
    if (x0 == x1 && y0 == y1) {
      return;
    }
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x0 += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y0 += sy;
    }
  }
}

}  // namespace ogf::tools
