#include "ogf/adapters/message_adapters.hpp"

#include <bot_core/pose_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

#include "ogf/messages/decode_message.hpp"
#include "ogf/messages/limits.hpp"

namespace ogf::adapters {
namespace {

std::int64_t fingerprintOf(const void* data, std::size_t size) {
  if (size < 8) return 0;
  const auto* p = static_cast<const std::uint8_t*>(data);
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | p[i];  // LCM encodes big-endian
  return static_cast<std::int64_t>(v);
}

// Times are microseconds since the Unix epoch. Any real clock lies in [0, 2^62) (2^62 µs is some 146,000
// years); bounding them there keeps every sum and difference of times downstream (a point's time is a
// scan's start plus its offset, interpolation divides time differences) inside int64.
constexpr std::int64_t kMaxUtime = std::int64_t{1} << 62;

std::optional<std::string> notATime(const char* field, std::int64_t utime) {
  if (utime >= 0 && utime < kMaxUtime) return std::nullopt;
  return std::string(field) + ": " + std::to_string(utime) + " is not a time (microseconds since 1970, in [0, 2^62))";
}

template <class Message>
Result<Message> decodeExactly(const void* data, std::size_t size, const char* type) {
  Message m;
  if (auto why = ogf::messages::decodeMessage(data, size, m)) return Error::inputDamaged(std::string(type) + ": " + *why);
  return m;
}

// The pose as the message gives it, before the checks every pose gets.
Result<fusion::Pose> decodePoseFields(const void* data, std::size_t size) {
  const std::int64_t fp = fingerprintOf(data, size);
  fusion::Pose pose;
  if (fp == ogf::odometry_t::getHash()) {
    auto m = decodeExactly<ogf::odometry_t>(data, size, "odometry_t");
    if (!m) return m.error();
    pose.utime = m->utime;
    pose.position = {m->position[0], m->position[1], m->position[2]};
    pose.orientation = Eigen::Quaterniond(m->orientation[0], m->orientation[1], m->orientation[2], m->orientation[3]);
    return pose;
  }
  if (fp == bot_core::pose_t::getHash()) {
    auto m = decodeExactly<bot_core::pose_t>(data, size, "bot_core.pose_t");
    if (!m) return m.error();
    pose.utime = m->utime;
    pose.position = {m->pos[0], m->pos[1], m->pos[2]};
    pose.orientation = Eigen::Quaterniond(m->orientation[0], m->orientation[1], m->orientation[2], m->orientation[3]);
    return pose;
  }
  return Error::inputDamaged("fingerprint matches neither ogf.odometry_t nor bot_core.pose_t");
}

}  // namespace

Result<fusion::Pose> decodePose(const void* data, std::size_t size) {
  auto pose = decodePoseFields(data, size);
  if (pose) {
    if (auto why = notATime("utime", pose->utime)) return Error::inputDamaged(*why);
  }
  return pose;
}

Status validateScan(const ogf::lidar_scan_t& s) {
  if (s.num_points < 0 || s.num_points > ogf::messages::kMaxScanPoints)
    return Error::inputDamaged("num_points: " + std::to_string(s.num_points) + " outside [0, " +
                 std::to_string(ogf::messages::kMaxScanPoints) + "]");
  const auto n = static_cast<std::size_t>(s.num_points);
  if (s.x.size() != n || s.y.size() != n || s.z.size() != n || s.time_offset_ns.size() != n)
    return Error::inputDamaged("arrays: lengths differ from num_points " + std::to_string(n));
  for (const auto& [field, utime] : {std::pair{"utime", s.utime}, std::pair{"device_utime_start", s.device_utime_start},
                                      std::pair{"device_utime_end", s.device_utime_end},
                                      std::pair{"host_utime_start", s.host_utime_start},
                                      std::pair{"host_utime_end", s.host_utime_end}})
    if (auto why = notATime(field, utime)) return Error::inputDamaged(*why);
  if (s.device_utime_end < s.device_utime_start) return Error::inputDamaged("device_utime_end: before device_utime_start");
  if (s.host_utime_end < s.host_utime_start) return Error::inputDamaged("host_utime_end: before host_utime_start");
  for (std::size_t i = 0; i < n; ++i) {
    if (s.time_offset_ns[i] < 0) return Error::inputDamaged("time_offset_ns[" + std::to_string(i) + "]: negative");
    // Coordinates are metres (lidar_scan_t); a sender never has a NaN or infinite point to give, so one
    // marks a corrupt message, refused whole and counted rather than mapped minus its bad rays.
    if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || !std::isfinite(s.z[i]))
      return Error::inputDamaged("x/y/z[" + std::to_string(i) + "]: not finite");
  }
  return okStatus();
}

fusion::ScanClock scanClockOf(std::int8_t time_source, ScanTimeBase base) {
  switch (base) {
    case ScanTimeBase::kDevice: return fusion::ScanClock::kDevice;
    case ScanTimeBase::kHost: return fusion::ScanClock::kHost;
    case ScanTimeBase::kAuto: break;
  }
  return time_source == ogf::lidar_scan_t::TIME_SOURCE_PPS_NMEA ? fusion::ScanClock::kDevice : fusion::ScanClock::kHost;
}

fusion::ScanClock scanClockOf(const ogf::lidar_scan_t& s, ScanTimeBase base) { return scanClockOf(s.time_source, base); }

std::int64_t scanStartOn(const ogf::lidar_scan_t& s, fusion::ScanClock clock) {
  return clock == fusion::ScanClock::kDevice ? s.device_utime_start : s.host_utime_start;
}

fusion::ScanPoints scanPointsOf(const ogf::lidar_scan_t& s, ScanTimeBase base) {
  return {scanStartOn(s, scanClockOf(s, base)), s.x, s.y, s.z, s.time_offset_ns};
}

}  // namespace ogf::adapters
