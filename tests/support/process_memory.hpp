// Test helper: a process's memory from /proc/<pid>/status: its resident set now (VmRSS), its peak (VmHWM,
// to show that bad input makes a daemon allocate nothing for what it claims), and a sampler of the
// resident set on its own thread while a load runs, so a test can bound the daemon's memory over the
// whole run, not just at its end.
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <thread>

namespace ogf::testing {

// VmRSS of `pid` in bytes; nullopt once the process is gone.
std::optional<std::int64_t> residentBytes(pid_t pid);
// VmHWM of `pid` in KiB; nullopt when the process or the line is not there.
std::optional<std::int64_t> peakResidentKiB(pid_t pid);

class RssSampler {
 public:
  RssSampler(pid_t pid, std::chrono::milliseconds period);
  ~RssSampler();
  RssSampler(const RssSampler&) = delete;
  RssSampler& operator=(const RssSampler&) = delete;

  std::int64_t firstBytes() const;  // the first sample (0 before any)
  std::int64_t peakBytes() const;
  int samples() const;

 private:
  pid_t pid_;
  mutable std::mutex mu_;
  std::int64_t first_ = 0, peak_ = 0;
  int samples_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace ogf::testing
