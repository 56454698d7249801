#include "ogf/driver_sources/udp_datagram.hpp"

#include <charconv>

namespace ogf::driver_sources {

std::string formatIpv4(std::uint32_t ip) {
  if (ip == 0) return {};
  return std::to_string(ip >> 24) + "." + std::to_string((ip >> 16) & 0xff) + "." +
         std::to_string((ip >> 8) & 0xff) + "." + std::to_string(ip & 0xff);
}

bool parseIpv4(const std::string& text, std::uint32_t& ip) {
  std::uint32_t result = 0;
  const char* p = text.data();
  const char* end = text.data() + text.size();
  for (int part = 0; part < 4; ++part) {
    unsigned value = 0;
    const auto [next, ec] = std::from_chars(p, end, value);
    if (ec != std::errc() || value > 255 || next == p) return false;
    result = (result << 8) | value;
    p = next;
    if (part < 3) {
      if (p == end || *p != '.') return false;
      ++p;
    }
  }
  if (p != end) return false;
  ip = result;
  return true;
}

}  // namespace ogf::driver_sources
