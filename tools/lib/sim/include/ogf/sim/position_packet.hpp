// The VLP-16 position (telemetry) packet: 512 bytes to port 8308 carrying the TOH stamp, the PPS status
// and the forwarded NMEA sentence (docs/wire-format.md §7.1, VLP-16 manual Table 9-3).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "ogf/sim/vlp16_model.hpp"

namespace ogf::sim::vlp16 {

inline constexpr std::size_t kPositionTimestampOffset = 198;  // 0xC6, LE uint32 µs since the hour
inline constexpr std::size_t kPpsStatusOffset = 202;          // 0xCA
inline constexpr std::size_t kNmeaOffset = 206;               // 0xCE, CR/LF-terminated, zero-padded
inline constexpr std::uint8_t kPpsLocked = 2;                 // 0 absent, 1 synchronising, 2 locked, 3 error

// The payload; the sentence is cut to the space left (306 bytes) if longer.
std::array<std::uint8_t, kPositionPayloadBytes> encodePositionPacket(std::uint32_t toh_us, std::uint8_t pps,
                                                                     std::string_view nmea);

}  // namespace ogf::sim::vlp16
