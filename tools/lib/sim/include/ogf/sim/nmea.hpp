// The NMEA 0183 sentence a GPS-synchronised VLP-16 forwards in its position packets: $GPRMC for a
// given UTC time, with the XOR checksum of the characters between '$' and '*'.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace ogf::sim {

// XOR of every character of `body` (the text between '$' and '*').
std::uint8_t nmeaChecksum(std::string_view body);

// A fixed antenna position for the simulated receiver (degrees; north and east positive).
struct GeoPosition {
  double latitude_deg = 48.1173;
  double longitude_deg = 11.5167;
};

// "$GPRMC,hhmmss,A,ddmm.mmmm,N,dddmm.mmmm,E,0.0,0.0,ddmmyy,,,A*CS\r\n" for the UTC second containing
// `utime` (µs since the epoch): the receiver reports the time of the last PPS edge.
std::string gprmcSentence(std::int64_t utime, const GeoPosition& where = {});

}  // namespace ogf::sim
