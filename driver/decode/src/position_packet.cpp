#include "ogf/velodyne/position_packet.hpp"

#include <algorithm>

#include "ogf/velodyne/wire_format.hpp"

namespace ogf::velodyne {

Result<PositionPacket> parsePositionPacket(std::span<const std::uint8_t> payload) {
  if (payload.size() != wire::kPositionPacketSize)
    return Error::inputDamaged("position packet: " + std::to_string(payload.size()) + " bytes, expected 512");
  const std::uint8_t* p = payload.data();
  PositionPacket packet;
  packet.toh_us = wire::readLe32(p + offsetof(wire::RawPositionPacket, timestamp));
  if (packet.toh_us >= wire::kMicrosecondsPerHour)
    return Error::inputDamaged("position packet: offset 198 (timestamp) holds " + std::to_string(packet.toh_us) +
                 " us, past the hour");
  const std::uint8_t pps = p[offsetof(wire::RawPositionPacket, pps_status)];
  if (pps > 3)
    return Error::inputDamaged("position packet: offset 202 (PPS status) holds " + std::to_string(pps) + ", expected 0..3");
  packet.pps = static_cast<PpsState>(pps);
  // The sentence starts at 206 and ends at CR, LF or NUL (vd telemetry_packet.cpp:105 reads up to 128).
  const std::uint8_t* nmea = p + offsetof(wire::RawPositionPacket, nmea);
  // The field holds a sentence or nothing (VLP-16 manual Table 9-3): it starts with '$' or NUL.
  if (nmea[0] != '$' && nmea[0] != 0)
    return Error::inputDamaged("position packet: offset 206 (NMEA) starts with byte " + std::to_string(nmea[0]) +
                 ", expected '$' or 0");
  std::size_t n = 0;
  while (n < packet.nmea_text.size() && nmea[n] != 0 && nmea[n] != '\r' && nmea[n] != '\n') {
    const std::uint8_t c = nmea[n];
    if (c < 0x20 || c > 0x7e) break;  // not printable ASCII: no sentence
    packet.nmea_text[n] = static_cast<char>(c);
    ++n;
  }
  packet.nmea_length = n > 0 && packet.nmea_text[0] == '$' ? n : 0;
  if (packet.nmea_length > 0) {
    auto fix = parseNmeaSentence(packet.nmea());
    if (fix) packet.fix = *fix;
  }
  return packet;
}

}  // namespace ogf::velodyne
