// The sensor models the simulator can be: laser angles and origins, product byte and firing schedule.
// The VLP-16 (the default) from docs/wire-format.md §4 and §6; the HDL-32E with the figures the driver's
// model table uses (driver/decode/include/ogf/velodyne/model.hpp: 1.152 µs per laser, 46.08 µs per block,
// docs/wire-format.md §4.3) and its nominal vertical angles (driver/decode/src/calibration.cpp).
// Both write the same 1206-byte packet layout (12 blocks × 32 channels).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "ogf/sim/vlp16_model.hpp"

namespace ogf::sim {

enum class LidarModelId { Vlp16, Hdl32e };

struct LidarModel {
  LidarModelId id = LidarModelId::Vlp16;
  std::string_view name;            // "VLP-16"
  std::uint8_t product_id = 0;      // byte 1205
  std::size_t lasers = 16;          // 16 or 32; channel c fires laser c % lasers
  std::array<double, 32> elevation_deg{};
  std::array<double, 32> vertical_offset_m{};
  std::int64_t block_ns = 0;        // one firing group (a block, or a dual block pair)

  // Time of channel `channel` of firing group `group` after the packet's first firing.
  std::int64_t channelOffsetNs(int group, int channel) const;
  // 12 firing groups per packet single, 6 dual (each block pair holds one group's two returns).
  std::int64_t packetPeriodNs(vlp16::ReturnMode mode) const {
    return (mode == vlp16::ReturnMode::Dual ? 6 : 12) * block_ns;
  }
};

const LidarModel& lidarModel(LidarModelId id);
// "vlp16", "hdl32e"; nullopt for anything else.
std::optional<LidarModelId> parseLidarModel(std::string_view name);
std::vector<std::string_view> lidarModelNames();

}  // namespace ogf::sim
