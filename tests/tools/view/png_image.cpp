#include "png_image.hpp"

#include <zlib.h>

#include <cstdlib>
#include <cstring>

namespace ogf::testing {
namespace {

std::uint32_t be32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

int paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

}  // namespace

std::optional<RgbImage> decodePng(std::span<const std::uint8_t> bytes, std::string& error) {
  static const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) {
    error = "not a PNG";
    return std::nullopt;
  }
  RgbImage img;
  int channels = 0;
  std::vector<std::uint8_t> idat;
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const std::uint32_t len = be32(&bytes[at]);
    if (at + 12 + len > bytes.size()) break;
    const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
    const std::uint8_t* data = &bytes[at + 8];
    if (type == "IHDR") {
      img.width = static_cast<int>(be32(data));
      img.height = static_cast<int>(be32(data + 4));
      const int depth = data[8], colour = data[9], interlace = data[12];
      channels = colour == 2 ? 3 : (colour == 6 ? 4 : 0);
      if (depth != 8 || channels == 0 || interlace != 0) {
        error = "unsupported PNG (depth " + std::to_string(depth) + ", colour type " + std::to_string(colour) + ")";
        return std::nullopt;
      }
    } else if (type == "IDAT") {
      idat.insert(idat.end(), data, data + len);
    }
    at += 12 + len;
  }
  if (channels == 0 || img.width <= 0 || img.height <= 0) {
    error = "no IHDR";
    return std::nullopt;
  }
  const auto w = static_cast<std::size_t>(img.width), h = static_cast<std::size_t>(img.height);
  const auto ch = static_cast<std::size_t>(channels);
  const std::size_t stride = w * ch;
  std::vector<std::uint8_t> raw((stride + 1) * h);
  uLongf raw_size = raw.size();
  if (uncompress(raw.data(), &raw_size, idat.data(), idat.size()) != Z_OK || raw_size != raw.size()) {
    error = "bad image data";
    return std::nullopt;
  }
  std::vector<std::uint8_t> prev(stride, 0), cur(stride);
  img.rgb.resize(w * h * 3);
  for (std::size_t y = 0; y < h; ++y) {
    const std::uint8_t* line = &raw[y * (stride + 1)];
    const int filter = line[0];
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= ch ? cur[i - ch] : 0;
      const int b = prev[i];
      const int c = i >= ch ? prev[i - ch] : 0;
      int v = line[1 + i];
      switch (filter) {
        case 1: v += a; break;
        case 2: v += b; break;
        case 3: v += (a + b) / 2; break;
        case 4: v += paeth(a, b, c); break;
        default: break;
      }
      cur[i] = static_cast<std::uint8_t>(v);
    }
    for (std::size_t x = 0; x < w; ++x) std::memcpy(&img.rgb[(y * w + x) * 3], &cur[x * ch], 3);
    std::swap(prev, cur);
  }
  return img;
}

}  // namespace ogf::testing
