#include "support/process_memory.hpp"

#include <algorithm>
#include <fstream>
#include <string>

namespace ogf::testing {

namespace {

// A "<field> <n> kB" line of /proc/<pid>/status, in KiB.
std::optional<std::int64_t> statusKiB(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string key;
  while (in >> key) {
    if (key == field) {
      std::int64_t kib = 0;
      if (in >> kib) return kib;
      return std::nullopt;
    }
    in.ignore(4096, '\n');
  }
  return std::nullopt;  // gone, or a zombie (no memory lines)
}

}  // namespace

std::optional<std::int64_t> residentBytes(pid_t pid) {
  const auto kib = statusKiB(pid, "VmRSS:");
  return kib ? std::optional<std::int64_t>(*kib * 1024) : std::nullopt;
}

std::optional<std::int64_t> peakResidentKiB(pid_t pid) { return statusKiB(pid, "VmHWM:"); }

RssSampler::RssSampler(pid_t pid, std::chrono::milliseconds period) : pid_(pid) {
  thread_ = std::thread([this, period] {
    while (!stop_) {
      if (const auto rss = residentBytes(pid_)) {
        std::lock_guard lk(mu_);
        if (samples_++ == 0) first_ = *rss;
        peak_ = std::max(peak_, *rss);
      }
      std::this_thread::sleep_for(period);
    }
  });
}

RssSampler::~RssSampler() {
  stop_ = true;
  thread_.join();
}

std::int64_t RssSampler::firstBytes() const {
  std::lock_guard lk(mu_);
  return first_;
}

std::int64_t RssSampler::peakBytes() const {
  std::lock_guard lk(mu_);
  return peak_;
}

int RssSampler::samples() const {
  std::lock_guard lk(mu_);
  return samples_;
}

}  // namespace ogf::testing
