// An LCM log opened for reading event by event, knowing how far through the file it is (for progress).
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>

namespace ogf::log_io {

class LogEvents {
 public:
  // Errors name the file: missing, unreadable, or not an LCM log.
  static Result<LogEvents> open(const std::filesystem::path& path);

  // The next event, or nullptr at the end.
  const lcm::LogEvent* next() { return log_->readNextEvent(); }
  // The fraction of the file read so far, in [0, 1].
  double fractionRead() const;

 private:
  LogEvents(std::unique_ptr<lcm::LogFile> log, std::uintmax_t size) : log_(std::move(log)), size_(size) {}
  std::unique_ptr<lcm::LogFile> log_;
  std::uintmax_t size_ = 0;
};

}  // namespace ogf::log_io
