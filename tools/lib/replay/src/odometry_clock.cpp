// The odometry's clock in a replay: see odometry_clock.hpp.
#include "ogf/replay/odometry_clock.hpp"

#include "ogf/velodyne/position_packet.hpp"

namespace ogf::replay {

std::optional<OdometryClock> parseOdometryClock(std::string_view name) {
  if (name == "capture") return OdometryClock::kCapture;
  if (name == "host") return OdometryClock::kHost;
  if (name == "auto") return OdometryClock::kAuto;
  return std::nullopt;
}

std::string_view odometryClockName(OdometryClock clock) {
  switch (clock) {
    case OdometryClock::kCapture: return "capture";
    case OdometryClock::kHost: return "host";
    case OdometryClock::kAuto: return "auto";
  }
  return "?";
}

void GpsTimeProbe::addPositionPayload(std::span<const std::uint8_t> payload) {
  if (decided()) return;
  const auto packet = velodyne::parsePositionPacket(payload);
  if (!packet) return;
  ++seen_;
  if (packet->pps == velodyne::PpsState::Locked && packet->gpsFixValid()) locked_ = true;
}

OdometryClock resolveOdometryClock(OdometryClock requested, const GpsTimeProbe& probe) {
  if (requested != OdometryClock::kAuto) return requested;
  return probe.hasGpsTime() ? OdometryClock::kCapture : OdometryClock::kHost;
}

std::string odometryClockReason(OdometryClock requested, const std::string& input, const GpsTimeProbe& probe) {
  if (requested == OdometryClock::kHost) return "--odometry-clock host";
  if (requested != OdometryClock::kAuto) return "--odometry-clock capture";
  return std::string("--odometry-clock auto: ") + input +
         (probe.hasGpsTime() ? " has PPS-locked GPS time, which ogf-driver stamps the packets with"
                             : " has no PPS-locked GPS time (" + std::to_string(probe.positionPackets()) +
                                   " position packets looked at), so ogf-driver stamps the replayed "
                                   "packets on the host clock");
}

}  // namespace ogf::replay
