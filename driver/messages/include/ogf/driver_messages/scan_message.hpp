// Fills the LCM messages ogf-driver publishes from the library's types: a decoded scan as
// ogf.lidar_scan_t, and raw payloads collected into an ogf.velodyne_packets_t batch. The message objects
// are reused, so their arrays keep their capacity from scan to scan.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "ogf/lidar_scan_t.hpp"
#include "ogf/velodyne/scan.hpp"
#include "ogf/velodyne_packets_t.hpp"

namespace ogf::driver {

// Overwrites `msg` with `scan`.
void fillScanMessage(const velodyne::Scan& scan, const std::string& frame_id, ogf::lidar_scan_t& msg);

class PacketBatch {
 public:
  void add(std::span<const std::uint8_t> payload, std::int64_t host_utime, int port,
           const std::string& sensor);
  bool empty() const { return msg_.num_packets == 0; }
  const ogf::velodyne_packets_t& message() const { return msg_; }
  void clear();

 private:
  ogf::velodyne_packets_t msg_{};
};

}  // namespace ogf::driver
