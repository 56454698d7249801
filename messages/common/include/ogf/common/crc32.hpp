// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320; the checksum of zlib, PNG and gzip) for file and
// record checksums. Incremental: crc32(b, crc32(a)) == crc32(a + b).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace ogf {

namespace detail {
constexpr std::array<std::uint32_t, 256> makeCrc32Table() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t n = 0; n < 256; ++n) {
    std::uint32_t c = n;
    for (int k = 0; k < 8; ++k) c = (c & 1U) != 0 ? 0xEDB88320U ^ (c >> 1) : c >> 1;
    t[n] = c;
  }
  return t;
}
inline constexpr std::array<std::uint32_t, 256> kCrc32Table = makeCrc32Table();
}  // namespace detail

// The CRC of `bytes` continuing from `crc` (0 to start).
constexpr std::uint32_t crc32(std::span<const std::byte> bytes, std::uint32_t crc = 0) {
  crc = ~crc;
  for (std::byte b : bytes) crc = detail::kCrc32Table[(crc ^ static_cast<std::uint32_t>(b)) & 0xFFU] ^ (crc >> 8);
  return ~crc;
}

inline std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0) {
  return crc32(std::span<const std::byte>(static_cast<const std::byte*>(data), size), crc);
}

}  // namespace ogf
