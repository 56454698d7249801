// Test helper: the odometry of a body standing still at the origin, as a CSV file ogf-replay --odometry
// and ogf-map --odometry read (utime,x,y,z,qw,qx,qy,qz), one pose every `step_us` over a span of time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>

namespace ogf::testing {

inline bool writeStaticOdometryCsv(const std::filesystem::path& path, std::int64_t first_utime,
                                   std::int64_t last_utime, std::int64_t step_us = 20'000) {
  std::ofstream out(path);
  out << "utime,x,y,z,qw,qx,qy,qz\n";
  for (std::int64_t t = first_utime; t <= last_utime + step_us - 1; t += step_us) out << t << ",0,0,0,1,0,0,0\n";
  return static_cast<bool>(out.flush());
}

}  // namespace ogf::testing
