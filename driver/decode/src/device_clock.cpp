#include "ogf/velodyne/device_clock.hpp"

namespace ogf::velodyne {
namespace {
constexpr std::int64_t kHourUs = 3'600'000'000LL;
constexpr std::int64_t kHalfHourUs = kHourUs / 2;
constexpr std::int64_t kDayUs = 24 * kHourUs;

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}
}  // namespace

std::int64_t placeInHour(std::uint32_t toh_us, std::int64_t reference_utime) {
  std::int64_t t = floorDiv(reference_utime, kHourUs) * kHourUs + toh_us;
  if (t - reference_utime > kHalfHourUs) t -= kHourUs;
  if (reference_utime - t > kHalfHourUs) t += kHourUs;
  return t;
}

bool DeviceClock::onPositionPacket(const PositionPacket& packet, std::int64_t host_utime) {
  if (packet.pps != PpsState::Locked || !packet.gpsFixValid()) return true;
  std::optional<std::int64_t> utc = packet.fix->utcMicroseconds();
  if (!utc) {
    // GGA carries no date: take the day that puts the time of day closest to the host clock.
    const std::int64_t day = floorDiv(host_utime, kDayUs) * kDayUs;
    std::int64_t candidate = day + packet.fix->microsecondsOfDay();
    if (candidate - host_utime > kDayUs / 2) candidate -= kDayUs;
    if (host_utime - candidate > kDayUs / 2) candidate += kDayUs;
    utc = candidate;
  }
  if (*utc - host_utime > kMaxNmeaAheadUs) return false;
  // The NMEA time is the GPS second the sentence describes; the packet's own counter pins it within the hour.
  gps_utime_ = placeInHour(packet.toh_us, *utc);
  gps_host_utime_ = host_utime;
  return true;
}

DeviceTime DeviceClock::toAbsolute(std::uint32_t toh_us, std::int64_t host_utime) const {
  if (gps_utime_ && host_utime - gps_host_utime_ <= kNmeaValidityUs &&
      host_utime >= gps_host_utime_ - kNmeaValidityUs)
    return {placeInHour(toh_us, *gps_utime_ + (host_utime - gps_host_utime_)), TimeSource::PpsNmea};
  return {placeInHour(toh_us, host_utime), TimeSource::HostHour};
}

}  // namespace ogf::velodyne
