#include "ogf/driver_messages/scan_message.hpp"

namespace ogf::driver {

void fillScanMessage(const velodyne::Scan& scan, const std::string& frame_id, ogf::lidar_scan_t& msg) {
  msg.utime = scan.device_utime_start;
  msg.seq = scan.seq;
  msg.frame_id = frame_id;
  msg.device_utime_start = scan.device_utime_start;
  msg.device_utime_end = scan.device_utime_end;
  msg.time_source = static_cast<std::int8_t>(scan.time_source);
  msg.host_utime_start = scan.host_utime_start;
  msg.host_utime_end = scan.host_utime_end;
  msg.model = static_cast<std::int8_t>(scan.model);
  msg.return_mode = static_cast<std::int8_t>(scan.return_mode);
  msg.rpm = scan.rpm;
  msg.cut_angle_deg = scan.cut_angle_deg;
  msg.packets_expected = scan.packets_expected;
  msg.packets_received = scan.packets_received;
  msg.packets_lost = scan.packets_lost;
  const std::size_t n = scan.points.size();
  msg.num_points = static_cast<std::int32_t>(n);
  msg.x.resize(n), msg.y.resize(n), msg.z.resize(n);
  msg.intensity.resize(n), msg.ring.resize(n), msg.laser_id.resize(n);
  msg.azimuth_deg.resize(n), msg.time_offset_ns.resize(n), msg.return_type.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const velodyne::ScanPoint& p = scan.points[i];
    msg.x[i] = p.x;
    msg.y[i] = p.y;
    msg.z[i] = p.z;
    msg.intensity[i] = p.intensity;
    msg.ring[i] = static_cast<std::int8_t>(p.ring);
    msg.laser_id[i] = static_cast<std::int8_t>(p.laser_id);
    msg.azimuth_deg[i] = p.azimuth_deg;
    msg.time_offset_ns[i] = p.time_offset_ns;
    msg.return_type[i] = static_cast<std::int8_t>(p.return_type);
  }
}

void PacketBatch::add(std::span<const std::uint8_t> payload, std::int64_t host_utime, int port,
                      const std::string& sensor) {
  if (msg_.num_packets == 0) {
    msg_.utime = host_utime;
    msg_.sensor_address = sensor;
  } else if (msg_.sensor_address != sensor) {
    msg_.sensor_address.clear();  // mixed senders: unknown
  }
  ++msg_.num_packets;
  msg_.host_utime.push_back(host_utime);
  msg_.port.push_back(port);
  msg_.length.push_back(static_cast<std::int32_t>(payload.size()));
  msg_.data.insert(msg_.data.end(), payload.begin(), payload.end());
  msg_.num_bytes = static_cast<std::int32_t>(msg_.data.size());
}

void PacketBatch::clear() {
  msg_.num_packets = 0;
  msg_.num_bytes = 0;
  msg_.host_utime.clear();
  msg_.port.clear();
  msg_.length.clear();
  msg_.data.clear();
}

}  // namespace ogf::driver
