// Test helper: builds 1206-byte data packets field by field (block azimuths, channel distances and
// reflectivities, timestamp, mode and product bytes).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ogf::testing {

class SyntheticPacket {
 public:
  SyntheticPacket(std::uint32_t toh_us = 0, std::uint8_t return_mode = 0x37, std::uint8_t product = 0x22) {
    bytes_.fill(0);
    for (int b = 0; b < 12; ++b) {
      bytes_[static_cast<std::size_t>(100 * b)] = 0xFF;
      bytes_[static_cast<std::size_t>(100 * b + 1)] = 0xEE;
    }
    put32(1200, toh_us);
    bytes_[1204] = return_mode;
    bytes_[1205] = product;
  }
  SyntheticPacket& azimuth(int block, std::uint16_t value) {
    put16(static_cast<std::size_t>(100 * block + 2), value);
    return *this;
  }
  // Azimuths start, start+step, ... (mod 36000), or pairs in dual mode.
  SyntheticPacket& azimuths(int start, int step, bool pairs = false) {
    for (int b = 0; b < 12; ++b)
      azimuth(b, static_cast<std::uint16_t>((start + step * (pairs ? b / 2 : b)) % 36000));
    return *this;
  }
  SyntheticPacket& channel(int block, int ch, std::uint16_t raw_distance, std::uint8_t reflectivity) {
    const auto at = static_cast<std::size_t>(100 * block + 4 + 3 * ch);
    put16(at, raw_distance);
    bytes_[at + 2] = reflectivity;
    return *this;
  }
  SyntheticPacket& allChannels(std::uint16_t raw_distance, std::uint8_t reflectivity) {
    for (int b = 0; b < 12; ++b)
      for (int c = 0; c < 32; ++c) channel(b, c, raw_distance, reflectivity);
    return *this;
  }
  SyntheticPacket& byte(std::size_t at, std::uint8_t value) {
    bytes_[at] = value;
    return *this;
  }
  const std::array<std::uint8_t, 1206>& bytes() const { return bytes_; }

 private:
  void put16(std::size_t at, std::uint16_t v) {
    bytes_[at] = static_cast<std::uint8_t>(v);
    bytes_[at + 1] = static_cast<std::uint8_t>(v >> 8);
  }
  void put32(std::size_t at, std::uint32_t v) {
    for (std::size_t i = 0; i < 4; ++i) bytes_[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
  std::array<std::uint8_t, 1206> bytes_{};
};

}  // namespace ogf::testing
