#include "ogf/map_io/scan_record.hpp"

#include <algorithm>

namespace ogf::map_io {

fusion::ScanPoints ScanRecord::points(TimeBase base) const {
  return {startOn(clock(base)), x, y, z, time_offset_ns};
}

void assignScan(const velodyne::Scan& scan, ScanRecord& out) {
  out.seq = scan.seq;
  out.device_utime_start = scan.device_utime_start;
  out.host_utime_start = scan.host_utime_start;
  out.time_source = static_cast<std::int8_t>(scan.time_source);
  const std::size_t n = scan.points.size();
  out.x.resize(n);
  out.y.resize(n);
  out.z.resize(n);
  out.time_offset_ns.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const velodyne::ScanPoint& p = scan.points[i];
    out.x[i] = p.x;
    out.y[i] = p.y;
    out.z[i] = p.z;
    out.time_offset_ns[i] = p.time_offset_ns;
  }
}

void assignScan(const ogf::lidar_scan_t& message, ScanRecord& out) {
  out.seq = message.seq;
  out.device_utime_start = message.device_utime_start;
  out.host_utime_start = message.host_utime_start;
  out.time_source = message.time_source;
  // The arrays are sized by num_points in the message; a hand-made message could disagree, so take the
  // shortest.
  const std::size_t n = std::min({static_cast<std::size_t>(std::max(message.num_points, 0)), message.x.size(),
                                  message.y.size(), message.z.size(), message.time_offset_ns.size()});
  out.x.assign(message.x.begin(), message.x.begin() + static_cast<std::ptrdiff_t>(n));
  out.y.assign(message.y.begin(), message.y.begin() + static_cast<std::ptrdiff_t>(n));
  out.z.assign(message.z.begin(), message.z.begin() + static_cast<std::ptrdiff_t>(n));
  out.time_offset_ns.assign(message.time_offset_ns.begin(),
                            message.time_offset_ns.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace ogf::map_io
