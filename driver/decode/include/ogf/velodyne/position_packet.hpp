// The 512-byte position (telemetry) packet on port 8308: top-of-hour timestamp, PPS state and the NMEA
// sentence from the GPS receiver (VLP-16 manual Tables 9-3/9-4; docs/wire-format.md §7).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "ogf/velodyne/nmea_sentence.hpp"
#include "ogf/common/result.hpp"

namespace ogf::velodyne {

// Values match driver_status_t's PPS_* constants.
enum class PpsState : std::uint8_t { Absent = 0, Synchronizing = 1, Locked = 2, Error = 3 };

struct PositionPacket {
  std::uint32_t toh_us = 0;
  PpsState pps = PpsState::Absent;
  std::array<char, 128> nmea_text{};  // the sentence without CR/LF; empty when none
  std::size_t nmea_length = 0;
  std::optional<NmeaFix> fix;  // set when the sentence parsed and its checksum matched

  std::string_view nmea() const { return {nmea_text.data(), nmea_length}; }
  bool gpsFixValid() const { return fix && fix->fix_valid; }
};

// Fails on a wrong size, a timestamp past the hour, a PPS byte above 3, or an NMEA field that starts with
// neither '$' nor NUL. A missing, unknown or corrupt sentence is not an error: the packet is returned
// without `fix`.
Result<PositionPacket> parsePositionPacket(std::span<const std::uint8_t> payload);

}  // namespace ogf::velodyne
