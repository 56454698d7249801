// Position packet encoder: zeros except the TOH stamp, the PPS status and the NMEA text (§4.5).
#include "ogf/sim/position_packet.hpp"

#include <algorithm>

#include "ogf/sim/byte_writer.hpp"

namespace ogf::sim::vlp16 {

std::array<std::uint8_t, kPositionPayloadBytes> encodePositionPacket(std::uint32_t toh_us, std::uint8_t pps,
                                                                     std::string_view nmea) {
  std::array<std::uint8_t, kPositionPayloadBytes> out{};
  putLe32(out, kPositionTimestampOffset, toh_us);
  out[kPpsStatusOffset] = pps;
  const std::size_t n = std::min(nmea.size(), kPositionPayloadBytes - kNmeaOffset);
  std::transform(nmea.begin(), nmea.begin() + static_cast<std::ptrdiff_t>(n), out.begin() + kNmeaOffset,
                 [](char c) { return static_cast<std::uint8_t>(c); });
  return out;
}

}  // namespace ogf::sim::vlp16
