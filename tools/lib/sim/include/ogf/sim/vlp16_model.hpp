// The VLP-16 as the simulator models it: laser angles and origins, the firing schedule and the packet
// period. Every figure comes from docs/wire-format.md §3 to §6 (and the manual sections it cites).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace ogf::sim::vlp16 {

// Return mode, with its byte at payload offset 1204 (docs/wire-format.md §3.6, manual Table 9-2).
enum class ReturnMode : std::uint8_t { Strongest = 0x37, Last = 0x38, Dual = 0x39 };
std::optional<ReturnMode> parseReturnMode(std::string_view name);  // "strongest", "last", "dual"
std::string_view toString(ReturnMode mode);

inline constexpr std::uint8_t kProductId = 0x22;  // VLP-16 / Puck LITE (§4.1)
inline constexpr int kLasers = 16;
inline constexpr int kBlocks = 12;            // firing blocks per data packet (§4.1)
inline constexpr int kChannelsPerBlock = 32;  // two firing sequences of 16 lasers (§4.1)
inline constexpr std::size_t kDataPayloadBytes = 1206;
inline constexpr std::size_t kPositionPayloadBytes = 512;
inline constexpr std::uint16_t kDataPort = 2368;
inline constexpr std::uint16_t kPositionPort = 8308;
inline constexpr double kDistanceUnitM = 0.002;  // distance LSB, 2 mm (§4.1)
inline constexpr double kMaxRangeM = 100.0;      // VLP-16 datasheet range

// Timing in integer nanoseconds, which every figure of §4.3 is exactly: 2.304 µs per firing, 55.296 µs
// per 16-firing sequence (with the 18.432 µs recharge), two sequences per block.
inline constexpr std::int64_t kFiringNs = 2304;
inline constexpr std::int64_t kSequenceNs = 55296;
inline constexpr std::int64_t kBlockNs = 2 * kSequenceNs;  // 110.592 µs

// Packet period, fixed by the firing cycle whatever the rpm (§4.3): 24 sequences = 1327.104 µs single,
// 12 sequences = 663.552 µs dual (each block pair holds one firing's two returns).
constexpr std::int64_t packetPeriodNs(ReturnMode mode) {
  return mode == ReturnMode::Dual ? 6 * kBlockNs : 12 * kBlockNs;
}

// The firing group a block belongs to: its own in single-return mode, the pair's in dual (§4.4).
constexpr int firingGroup(int block, ReturnMode mode) { return mode == ReturnMode::Dual ? block / 2 : block; }

// Time of channel `channel` (0..31) of firing group `group` after the packet's first firing (§4.3):
// t = 110.592 g + 55.296 s + 2.304 laser, s = channel / 16, laser = channel % 16.
constexpr std::int64_t channelOffsetNs(int group, int channel) {
  return group * kBlockNs + (channel / kLasers) * kSequenceNs + (channel % kLasers) * kFiringNs;
}

// Elevation of each laser id, degrees (§4.2).
inline constexpr std::array<double, kLasers> kElevationDeg = {-15, 1, -13, 3, -11, 5, -9, 7,
                                                               -7,  9, -5, 11, -3, 13, -1, 15};
// Vertical offset of each laser's origin, metres, added to z (§4.2, ros2 VLP16db.yaml).
inline constexpr std::array<double, kLasers> kVerticalOffsetM = {
    0.0112, -0.0007, 0.0097, -0.0022, 0.0081, -0.0037, 0.0066, -0.0051,
    0.0051, -0.0066, 0.0037, -0.0081, 0.0022, -0.0097, 0.0007, -0.0112};

}  // namespace ogf::sim::vlp16
