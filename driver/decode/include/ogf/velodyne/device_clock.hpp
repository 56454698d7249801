// Turns the sensor's microseconds-past-the-hour counter into absolute time. With PPS locked and a valid
// NMEA time, the hour comes from the GPS; otherwise from the host clock. Either way the counter is placed
// in the hour that puts it within 30 minutes of the reference (ros time_conversion.hpp:51-62; vd
// time_conversion.cpp:12-29), never "host hour + device minutes" blindly.
#pragma once

#include <cstdint>
#include <optional>

#include "ogf/velodyne/position_packet.hpp"

namespace ogf::velodyne {

// Values match lidar_scan_t's TIME_SOURCE_* constants.
enum class TimeSource : std::uint8_t { HostHour = 0, PpsNmea = 1 };

struct DeviceTime {
  std::int64_t utime = 0;  // microseconds since the Unix epoch
  TimeSource source = TimeSource::HostHour;
};

// The absolute time within 30 minutes of `reference_utime` whose minutes and seconds are `toh_us`.
std::int64_t placeInHour(std::uint32_t toh_us, std::int64_t reference_utime);

class DeviceClock {
 public:
  // An NMEA time older than this (host clock) no longer anchors the hour.
  static constexpr std::int64_t kNmeaValidityUs = 10'000'000;

  // A GPS time further than this ahead of the host clock is refused: a forged or broken receiver, not a
  // clock to follow (a day allows a host clock set by hand). Earlier times are plausible: a capture
  // replayed later carries the date it was recorded on.
  static constexpr std::int64_t kMaxNmeaAheadUs = 86'400'000'000LL;

  // Remembers the GPS time when the packet's PPS is locked and its sentence is a valid fix. False when
  // that time is refused (more than kMaxNmeaAheadUs ahead of host_utime): the hour stays as it was.
  bool onPositionPacket(const PositionPacket& packet, std::int64_t host_utime);
  DeviceTime toAbsolute(std::uint32_t toh_us, std::int64_t host_utime) const;

 private:
  std::optional<std::int64_t> gps_utime_;  // GPS time of the last good sentence
  std::int64_t gps_host_utime_ = 0;        // host time it arrived
};

}  // namespace ogf::velodyne
