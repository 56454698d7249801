// Writes a simulated Velodyne capture (VLP-16 or HDL-32E) to PCAP: data packets at the real packet
// period, a position packet (GPRMC, PPS locked) after every 14th data packet (a sensor sends about one
// per 14 data packets, docs/wire-format.md §7.1).
// Each frame's pcap stamp is the absolute time of its TOH stamp, so host time and device time agree.
#pragma once

#include <cstdint>
#include <string>

#include "ogf/sim/lidar_simulator.hpp"
#include "ogf/sim/nmea.hpp"
#include "ogf/common/result.hpp"

namespace ogf::sim {

inline constexpr std::uint64_t kDataPacketsPerPositionPacket = 14;

struct CaptureSummary {
  std::uint64_t data_packets = 0;
  std::uint64_t position_packets = 0;
  std::int64_t first_utime = 0;
  std::int64_t last_utime = 0;
};

// The data packets whose first firing falls within `duration_s` of the start.
std::uint64_t dataPacketCount(const LidarSimulator& sim, double duration_s);

Result<CaptureSummary> writeCapture(const LidarSimulator& sim, double duration_s, const std::string& pcap_path,
                                    const GeoPosition& where = {});

}  // namespace ogf::sim
