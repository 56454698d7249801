// ogf-mapper's two clocks: the steady clock times intervals (snapshots, keyframes, silence, the worker's
// heartbeat), the wall clock stamps messages and judges the inputs' times against the host's.
#pragma once

#include <chrono>
#include <cstdint>

namespace ogf::mapper_daemon {

inline std::int64_t steadyUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

inline std::int64_t wallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Milliseconds from `since` until now, for the log and the status.
inline double msSince(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace ogf::mapper_daemon
