// One lidar scan as ogf-map holds it, whatever the input it came from (a PCAP through the driver's
// decoder, an lcm-logger record of lidar_scan_t): the points in the sensor frame as the structure of arrays
// fusion::ScanPoints views, each point's time offset, and the start time on both clocks so the command line
// can choose which clock the odometry is on (--time auto|device|host), and whether the device time is UTC.
#pragma once

#include <ogf/adapters/message_adapters.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/deskew.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/velodyne/scan.hpp>

#include <cstdint>
#include <vector>

namespace ogf::map_io {

// Which clock the odometry's utime is on: the sensor's (device_utime_start), the host's receive time
// (host_utime_start), or auto: the device time of scans whose device time is UTC (GPS/PPS locked), the host
// time of the others (the rule ogf-mapper follows, adapters::scanClockOf).
using TimeBase = adapters::ScanTimeBase;

struct ScanRecord {
  std::int64_t seq = 0;
  std::int64_t device_utime_start = 0;
  std::int64_t host_utime_start = 0;
  std::int8_t time_source = 0;               // lidar_scan_t::TIME_SOURCE_*: whether the device time is UTC
  std::vector<float> x, y, z;                // metres, sensor frame
  std::vector<std::int32_t> time_offset_ns;  // from the scan's first firing

  std::size_t size() const { return x.size(); }
  // The clock `base` times this scan on.
  fusion::ScanClock clock(TimeBase base) const { return adapters::scanClockOf(time_source, base); }
  std::int64_t startOn(fusion::ScanClock c) const {
    return c == fusion::ScanClock::kHost ? host_utime_start : device_utime_start;
  }
  // A view of the points with the start time on the clock of `base`; valid while this record is unchanged.
  fusion::ScanPoints points(TimeBase base) const;
};

// Fills `out` (reusing its buffers) from a decoded scan or from a lidar_scan_t message.
void assignScan(const velodyne::Scan& scan, ScanRecord& out);
void assignScan(const ogf::lidar_scan_t& message, ScanRecord& out);

}  // namespace ogf::map_io
