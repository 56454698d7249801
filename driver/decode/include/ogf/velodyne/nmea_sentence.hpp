// NMEA 0183 sentences a Velodyne forwards from its GPS receiver inside position packets: $GPRMC (time,
// date, fix status, position, speed, course) and $GPGGA (time, fix quality, position), any talker id,
// checked against their XOR checksum (NMEA 0183 §5.3; vd telemetry_packet.cpp:18-96).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "ogf/common/result.hpp"

namespace ogf::velodyne {

struct NmeaFix {
  enum class Kind : std::uint8_t { Rmc, Gga };
  Kind kind = Kind::Rmc;
  bool fix_valid = false;  // RMC status 'A', or GGA quality > 0
  int hour = 0, minute = 0;
  double second = 0.0;
  std::optional<int> year, month, day;                // RMC only
  std::optional<double> latitude_deg, longitude_deg;  // north and east positive
  std::optional<double> speed_knots, course_deg;      // RMC only

  std::int64_t microsecondsOfDay() const;
  // Microseconds since the Unix epoch, when the sentence carries a date.
  std::optional<std::int64_t> utcMicroseconds() const;
};

// Parses one sentence ("$GPRMC,...*hh", trailing CR/LF allowed). Errors name the field that was wrong.
Result<NmeaFix> parseNmeaSentence(std::string_view sentence);

}  // namespace ogf::velodyne
