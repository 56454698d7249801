// Which clock the odometry ogf-replay publishes is stamped on, so that it meets the scans ogf-driver makes
// of the replayed packets. The driver stamps a scan with the sensor's GPS time when its position packets
// carry a PPS-locked fix (the capture's own clock, the one a recorded odometry is on), else with the host
// clock at which the replayed packets arrive (ogf/velodyne/device_clock.hpp; ogf-mapper's time_base auto
// follows the same rule). `capture` publishes each pose as recorded; `host` moves each pose's utime to the
// host time at which the replay sends what was captured at that utime (replay start host time + capture
// time since the replay's origin / speed: a constant offset at speed 1); `auto` picks `host` unless the
// capture has PPS-locked GPS time.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace ogf::replay {

enum class OdometryClock { kCapture, kHost, kAuto };

// "capture", "host", "auto"; nullopt for anything else.
std::optional<OdometryClock> parseOdometryClock(std::string_view name);
std::string_view odometryClockName(OdometryClock clock);

// Looks at a capture's position packets (the payloads sent to port 8308) for the GPS time the driver
// would use: a PPS-locked packet whose NMEA sentence is a valid fix. Malformed payloads are ignored.
class GpsTimeProbe {
 public:
  // Position packets looked at before deciding that a capture without a lock among them has no GPS time
  // (the sensor sends several a second; a receiver that locks later than this is not the time base the
  // driver starts with).
  static constexpr std::int64_t kMaxPackets = 200;

  void addPositionPayload(std::span<const std::uint8_t> payload);
  // True once the answer cannot change: a locked packet was seen, or kMaxPackets were.
  bool decided() const { return locked_ || seen_ >= kMaxPackets; }
  bool hasGpsTime() const { return locked_; }
  std::int64_t positionPackets() const { return seen_; }

 private:
  std::int64_t seen_ = 0;
  bool locked_ = false;
};

// `auto` resolved: host unless the capture has GPS time.
OdometryClock resolveOdometryClock(OdometryClock requested, const GpsTimeProbe& probe);

// Why the odometry is on the clock it is on, for the log: the flag as given, or for `auto` what the probe
// found in `input` (the capture's name).
std::string odometryClockReason(OdometryClock requested, const std::string& input, const GpsTimeProbe& probe);

}  // namespace ogf::replay
