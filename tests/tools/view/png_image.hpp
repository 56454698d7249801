// Test helper: decodes a PNG (8-bit RGB or RGBA, no interlace, as Chromium's screenshots are) into RGB
// pixels with zlib, so a test can read what a browser drew.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ogf::testing {

struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // row-major, 3 bytes a pixel
  const std::uint8_t* at(int x, int y) const {
    return &rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3];
  }
};

// nullopt (with `error` set) when the bytes are not a PNG this reads.
std::optional<RgbImage> decodePng(std::span<const std::uint8_t> bytes, std::string& error);

}  // namespace ogf::testing
