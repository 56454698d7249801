// One UDP datagram as a packet source delivers it: sender, ports, receive time and the payload (a view
// into the source's buffer, valid until the source reads the next one).
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace ogf::driver_sources {

struct UdpDatagram {
  std::uint32_t source_ip = 0;  // host order, 0 when unknown
  std::uint16_t source_port = 0;
  std::uint16_t destination_port = 0;
  std::int64_t utime = 0;  // receive (or capture) time, microseconds since the Unix epoch
  std::span<const std::uint8_t> payload;
};

// "192.168.1.201"; "" for 0.
std::string formatIpv4(std::uint32_t ip);
// Parses a dotted quad; false on anything else.
bool parseIpv4(const std::string& text, std::uint32_t& ip);

}  // namespace ogf::driver_sources
