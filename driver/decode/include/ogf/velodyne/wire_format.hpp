// The Velodyne 1206-byte data packet and 512-byte position packet as they arrive in a UDP payload
// (VLP-16 manual §9, Tables 9-2 to 9-4; docs/wire-format.md §3 and §7), shared by the VLP-16, Puck
// Hi-Res, VLP-32C and HDL-32E. The structs hold bytes only, so they have no padding, no alignment needs
// and no host byte order; multi-byte fields are read with the little-endian helpers below.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ogf::velodyne::wire {

inline constexpr std::size_t kDataPacketSize = 1206;     // 12 x 100 + 4 + 2 (ros rawdata.h:62-65)
inline constexpr std::size_t kPositionPacketSize = 512;  // VLP-16 manual Table 9-3
// The timestamp counts microseconds past the top of the hour: 0 to 3 599 999 999 (VLP-16 manual §9.3.1.3).
inline constexpr std::uint32_t kMicrosecondsPerHour = 3'600'000'000U;
inline constexpr int kBlocksPerPacket = 12;
inline constexpr int kChannelsPerBlock = 32;
// Bytes FF EE on the wire, read little-endian (ros rawdata.h:71, vd types.h:120-125).
inline constexpr std::uint16_t kUpperBankFlag = 0xEEFF;
inline constexpr std::uint16_t kAzimuthUnitsPerTurn = 36000;  // 0.01 degree units

// Byte 1204 (vd types.h:104-108; manual Table 9-2).
// Byte 1204 of firmware that does not report its return mode (HDL-32E before 2.2.20).
inline constexpr std::uint8_t kReturnModeUnreported = 0x00;
inline constexpr std::uint8_t kReturnModeStrongest = 0x37;
inline constexpr std::uint8_t kReturnModeLast = 0x38;
inline constexpr std::uint8_t kReturnModeDual = 0x39;

// Byte 1205 (vd types.h:94-102; VeloView vtkDataPacket.h:48-61).
inline constexpr std::uint8_t kProductHdl32E = 0x21;
inline constexpr std::uint8_t kProductVlp16 = 0x22;
inline constexpr std::uint8_t kProductPuckHiRes = 0x24;
inline constexpr std::uint8_t kProductVlp32C = 0x28;

struct RawChannel {
  std::uint8_t distance[2];  // LE uint16, x distance resolution (2 mm VLP-16/HDL-32E, 4 mm VLP-32C)
  std::uint8_t reflectivity;
};

struct RawBlock {
  std::uint8_t flag[2];     // FF EE
  std::uint8_t azimuth[2];  // LE uint16, 0..35999, azimuth of the block's first firing
  RawChannel channels[kChannelsPerBlock];
};

struct RawDataPacket {
  RawBlock blocks[kBlocksPerPacket];
  std::uint8_t timestamp[4];  // LE uint32, microseconds past the top of the hour, first firing
  std::uint8_t return_mode;
  std::uint8_t product_id;
};

struct RawPositionPacket {
  std::uint8_t unused[198];   // HDL-32E gyro/temperature/accelerometer at 14..37; newer firmware
                              // temperatures at 187..197 (vd telemetry_packet.cpp:106-116)
  std::uint8_t timestamp[4];  // 198: LE uint32, microseconds past the hour
  std::uint8_t pps_status;    // 202: 0 absent, 1 synchronizing, 2 locked, 3 error (Table 9-4)
  std::uint8_t thermal[3];    // 203..205
  std::uint8_t nmea[306];     // 206..511: NMEA sentence, CR/LF terminated, NUL padded
};

static_assert(sizeof(RawChannel) == 3);
static_assert(sizeof(RawBlock) == 100);
static_assert(sizeof(RawDataPacket) == kDataPacketSize);
static_assert(sizeof(RawPositionPacket) == kPositionPacketSize);
static_assert(offsetof(RawDataPacket, timestamp) == 1200);
static_assert(offsetof(RawDataPacket, return_mode) == 1204);
static_assert(offsetof(RawDataPacket, product_id) == 1205);
static_assert(offsetof(RawPositionPacket, timestamp) == 198);
static_assert(offsetof(RawPositionPacket, pps_status) == 202);
static_assert(offsetof(RawPositionPacket, nmea) == 206);

// Endian-safe reads: byte by byte, independent of host order and alignment.
constexpr std::uint16_t readLe16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
constexpr std::uint32_t readLe32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

}  // namespace ogf::velodyne::wire
