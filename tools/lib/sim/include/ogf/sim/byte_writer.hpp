// Little- and big-endian stores into byte buffers: the wire formats the simulator writes (Velodyne
// payloads are little-endian, Ethernet/IP/UDP headers big-endian) never depend on the host's byte order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace ogf::sim {

inline void putLe16(std::span<std::uint8_t> b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v & 0xFFu);
  b[at + 1] = static_cast<std::uint8_t>(v >> 8);
}
inline void putLe32(std::span<std::uint8_t> b, std::size_t at, std::uint32_t v) {
  for (std::size_t i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>((v >> (8 * i)) & 0xFFu);
}
inline void putBe16(std::span<std::uint8_t> b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v >> 8);
  b[at + 1] = static_cast<std::uint8_t>(v & 0xFFu);
}

}  // namespace ogf::sim
