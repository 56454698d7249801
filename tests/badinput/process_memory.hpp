// Test helper: a process's peak resident set size (VmHWM in /proc/<pid>/status), to show that bad input
// makes a daemon allocate nothing for what it claims.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>

namespace ogf::testing {

// VmHWM in KiB, or nullopt when the process or the line is not there.
inline std::optional<std::int64_t> peakResidentKiB(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == "VmHWM:") {
      std::int64_t kib = 0;
      if (in >> kib) return kib;
      return std::nullopt;
    }
    std::getline(in, key);
  }
  return std::nullopt;
}

}  // namespace ogf::testing
