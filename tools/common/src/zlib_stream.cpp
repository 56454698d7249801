// Stored deflate blocks of at most 65535 bytes, zlib header 0x78 0x01, Adler-32 trailer (big-endian).
#include "ogf/tools/zlib_stream.hpp"

#include <algorithm>

namespace ogf::tools {

std::uint32_t adler32(std::span<const std::uint8_t> bytes) {
  constexpr std::uint32_t kMod = 65521;
  std::uint32_t a = 1;
  std::uint32_t b = 0;
  for (std::uint8_t v : bytes) {
    a = (a + v) % kMod;
    b = (b + a) % kMod;
  }
  return (b << 16) | a;
}

std::vector<std::uint8_t> zlibStored(std::span<const std::uint8_t> data) {
  std::vector<std::uint8_t> out = {0x78, 0x01};  // deflate, 32 KiB window; 0x7801 % 31 == 0
  std::size_t pos = 0;
  do {
    const std::size_t len = std::min<std::size_t>(65535, data.size() - pos);
    const bool last = pos + len == data.size();
    out.push_back(last ? 1 : 0);  // BFINAL, BTYPE = 00 (stored)
    const auto n = static_cast<std::uint16_t>(len);
    const auto nn = static_cast<std::uint16_t>(~n);
    out.push_back(static_cast<std::uint8_t>(n & 0xFFU));
    out.push_back(static_cast<std::uint8_t>(n >> 8));
    out.push_back(static_cast<std::uint8_t>(nn & 0xFFU));
    out.push_back(static_cast<std::uint8_t>(nn >> 8));
    out.insert(out.end(), data.begin() + static_cast<std::ptrdiff_t>(pos),
               data.begin() + static_cast<std::ptrdiff_t>(pos + len));
    pos += len;
  } while (pos < data.size());
  const std::uint32_t sum = adler32(data);
  for (int shift = 24; shift >= 0; shift -= 8) {
    out.push_back(static_cast<std::uint8_t>((sum >> shift) & 0xFFU));
  }
  return out;
}

}  // namespace ogf::tools
