// One decoded scan: at most one revolution, cut at the configured azimuth, with the times and packet
// accounting lidar_scan_t publishes.
#pragma once

#include <cstdint>
#include <vector>

#include "ogf/velodyne/device_clock.hpp"
#include "ogf/velodyne/model.hpp"

namespace ogf::velodyne {

struct ScanPoint {
  float x, y, z;
  float distance_m;
  float azimuth_deg;
  std::int32_t time_offset_ns;  // firing time minus device_utime_start
  std::uint8_t intensity;
  std::uint8_t ring;
  std::uint8_t laser_id;
  ReturnType return_type;
};

struct Scan {
  std::int64_t seq = 0;
  std::int64_t device_utime_start = 0;  // first firing
  std::int64_t device_utime_end = 0;    // last firing
  TimeSource time_source = TimeSource::HostHour;
  std::int64_t host_utime_start = 0;  // receive time of the first and last packet
  std::int64_t host_utime_end = 0;
  Model model = Model::Unknown;
  ReturnMode return_mode = ReturnMode::Strongest;
  float rpm = 0.0f;
  float cut_angle_deg = 0.0f;
  std::int32_t packets_expected = 0;
  std::int32_t packets_received = 0;
  std::int32_t packets_lost = 0;
  bool starts_at_cut = false;  // false for the first scan of a stream and after a long gap
  bool ends_at_cut = false;    // false for the last scan and before a long gap
  std::vector<ScanPoint> points;

  void clear();
};

}  // namespace ogf::velodyne
