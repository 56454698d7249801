// A VLP-16 data packet as values, and its 1206-byte little-endian wire encoding (docs/wire-format.md §3.1).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "ogf/sim/vlp16_model.hpp"

namespace ogf::sim::vlp16 {

struct FiringBlock {
  std::uint16_t azimuth = 0;                           // 0.01°, 0..35999, of the block's first firing
  std::array<std::uint16_t, kChannelsPerBlock> distance{};  // 2 mm units, 0 = no return
  std::array<std::uint8_t, kChannelsPerBlock> reflectivity{};
};

struct DataPacket {
  std::array<FiringBlock, kBlocks> blocks{};
  std::uint32_t toh_us = 0;  // µs since the top of the hour of the packet's first firing
  ReturnMode mode = ReturnMode::Strongest;
  std::uint8_t product_id = kProductId;
};

inline constexpr std::uint16_t kBlockFlag = 0xEEFF;  // bytes FF EE (§4.1, "upper bank")

// Offsets within the payload (§4.1).
inline constexpr std::size_t kBlockBytes = 100;
inline constexpr std::size_t kTimestampOffset = 1200;
inline constexpr std::size_t kReturnModeOffset = 1204;
inline constexpr std::size_t kProductIdOffset = 1205;

void encode(const DataPacket& packet, std::span<std::uint8_t, kDataPayloadBytes> out);

}  // namespace ogf::sim::vlp16
