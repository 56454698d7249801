// ogf-map --report-every: a long drive's cost over time, one row per interval of scan time: the scans
// mapped in it, their mean and largest wall time per scan, and at its end the map's own count of bytes
// (memoryBytes), the process's resident set and the allocated cells. A flat cost per scan and memory that
// grows with the area seen, not with time, are what a robot mapping for hours needs.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>

namespace ogf::map_io {

struct DriveSample {
  std::int64_t utime = 0;        // the scan's start, us
  double milliseconds = 0.0;     // wall time to map it
  std::size_t mapBytes = 0;      // memoryBytes() after it
  std::size_t cells = 0;         // allocated cells after it
};

class DriveReport {
 public:
  // One row every `intervalSeconds` of scan time, written to `out`.
  DriveReport(double intervalSeconds, std::FILE* out);
  void add(const DriveSample& sample);
  // The last, partial interval.
  void finish();

 private:
  void row();
  double interval_;
  std::FILE* out_;
  std::optional<std::int64_t> first_;
  std::int64_t intervalStart_ = 0;
  int index_ = 0;
  std::int64_t scans_ = 0;
  double sumMs_ = 0.0, maxMs_ = 0.0;
  DriveSample last_;
};

// VmRSS of this process, bytes (0 when /proc is not readable).
std::size_t residentBytes();

}  // namespace ogf::map_io
