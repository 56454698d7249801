// Test helper: a small known scene, a sensor at the origin facing a wall at x = wall_x (the plane, cut to
// |y| < 3 m and |z| < 1 m by the fan's angles), as a ScanRecord of 16 rings x 120 azimuths over ±30°.
#pragma once

#include <cmath>
#include <cstdint>

#include "ogf/map_io/scan_record.hpp"

namespace ogf::testing {

inline map_io::ScanRecord wallScan(double wall_x, std::int64_t start_utime = 1'700'000'000'000'000) {
  map_io::ScanRecord s;
  s.device_utime_start = start_utime;
  s.host_utime_start = start_utime;
  for (int ring = 0; ring < 16; ++ring) {
    const double elev = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (int a = 0; a < 120; ++a) {
      const double az = (-30.0 + 0.5 * a) * M_PI / 180.0;
      const double dx = std::cos(elev) * std::cos(az);
      const double r = wall_x / dx;
      s.x.push_back(static_cast<float>(wall_x));
      s.y.push_back(static_cast<float>(r * std::cos(elev) * std::sin(az)));
      s.z.push_back(static_cast<float>(r * std::sin(elev)));
      s.time_offset_ns.push_back(a * 1000);
    }
  }
  return s;
}

}  // namespace ogf::testing
