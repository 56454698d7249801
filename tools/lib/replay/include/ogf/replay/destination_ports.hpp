// Which UDP port a replayed datagram goes to: a Velodyne's data packets (captured to 2368) to the data
// port, its position packets (captured to 8308) to the position port, anything else to the port it was
// captured with, so a capture of a sensor on non-standard ports still replays faithfully.
#pragma once

#include <cstdint>

namespace ogf::replay {

struct DestinationPorts {
  std::uint16_t data = 2368;
  std::uint16_t position = 8308;

  static constexpr std::uint16_t kCapturedData = 2368;
  static constexpr std::uint16_t kCapturedPosition = 8308;

  std::uint16_t forCaptured(std::uint16_t captured_port) const {
    if (captured_port == kCapturedData) return data;
    if (captured_port == kCapturedPosition) return position;
    return captured_port;
  }
};

}  // namespace ogf::replay
