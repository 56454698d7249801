// Sensor models of the 1206-byte packet family, their return modes and per-point return types, and the
// fixed numbers each model's packets follow (lasers, firing timing, distance unit).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace ogf::velodyne {

// Values match lidar_scan_t's MODEL_* constants.
enum class Model : std::uint8_t { Unknown = 0, Vlp16 = 1, Vlp16HiRes = 2, Vlp32C = 3, Hdl32E = 4 };

// Values match lidar_scan_t's RETURN_MODE_* constants.
enum class ReturnMode : std::uint8_t { Strongest = 1, Last = 2, Dual = 3 };

// Values match lidar_scan_t's RETURN_* constants.
enum class ReturnType : std::uint8_t { Strongest = 1, Last = 2, Both = 3, SecondStrongest = 4 };

struct ModelTraits {
  Model model;
  std::string_view name;
  int lasers;                    // 16 or 32
  int firings_per_block;         // laser firing sequences in one block: 2 (VLP-16) or 1 (32 lasers)
  double distance_resolution_m;  // vd calib_db.cpp resolutions: 2 mm, VLP-32C 4 mm
  double block_duration_us;      // time covered by one block's firings
  double sequence_duration_us;   // one firing sequence, recharge included
};

// VLP-16 / Hi-Res: 2.304 us per laser, 55.296 us per sequence, two per block (manual §8.1; ros
// rawdata.h:75-79). VLP-32C: lasers fire in pairs every 2.304 us, 55.296 us per block (VLP-32C manual;
// vd packet_decoder.cpp buildTimings). HDL-32E: 1.152 us per laser, 46.08 us per block (HDL-32E
// application note 63-9277 p.20; vd buildTimings).
const ModelTraits& traits(Model model);

// Time of one laser firing after the block's first one, microseconds; `channel` is 0..31.
double channelTimeInBlockUs(Model model, int channel);

// Which firing sequence of the block a channel belongs to (0 or 1 on the VLP-16, always 0 otherwise).
int sequenceOfChannel(Model model, int channel);

// Laser id of a channel: channel mod 16 on the VLP-16 and Hi-Res, the channel on 32-laser models.
int laserOfChannel(Model model, int channel);

// Nominal time between two data packets (the firing cycle fixes it, not the RPM; docs/wire-format.md §4.4).
double packetPeriodUs(Model model, ReturnMode mode);

// The most returns one revolution of `model` holds: dual return (two per firing, 384 a packet) at the
// slowest rate the sensors turn, 300 rpm (manuals: 300-1200 rpm), from the packet rate the firing cycle
// fixes. VLP-16 about 116 000, HDL-32E about 278 000. nullopt for Unknown.
std::optional<std::int64_t> mostPointsPerRevolution(Model model);

std::string_view modelName(Model model);
std::string_view returnModeName(ReturnMode mode);
std::string_view returnTypeName(ReturnType type);

// "VLP-16", "vlp16", "puck", "puck-lite", "VLP-16-HiRes", "hires", "puck-hi-res", "VLP-32C", "vlp32c",
// "HDL-32E", "hdl32e", case-insensitive. nullopt for anything else.
std::optional<Model> parseModelName(std::string_view name);
// "strongest", "last", "dual".
std::optional<ReturnMode> parseReturnModeName(std::string_view name);

// From byte 1204; nullopt when the byte is none of 0x37/0x38/0x39 (HDL-32E before firmware 2.2.20).
std::optional<ReturnMode> returnModeFromByte(std::uint8_t byte);

// From byte 1205 alone. 0x21 maps to HDL-32E although early VLP-16 firmware reports it too: use
// ModelDetector for that case.
std::optional<Model> modelFromProductId(std::uint8_t product_id);

}  // namespace ogf::velodyne
