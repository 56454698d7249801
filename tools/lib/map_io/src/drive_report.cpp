// One row per interval of scan time, and the resident set from /proc.
#include "ogf/map_io/drive_report.hpp"

#include <unistd.h>

#include <fstream>

namespace ogf::map_io {

DriveReport::DriveReport(double intervalSeconds, std::FILE* out) : interval_(intervalSeconds), out_(out) {
  std::fprintf(out_, "%-9s %7s %9s %9s %9s %9s %11s\n", "interval", "scans", "mean ms", "max ms", "map MB",
               "RSS MB", "cells");
}

void DriveReport::add(const DriveSample& sample) {
  if (!first_) {
    first_ = sample.utime;
    intervalStart_ = sample.utime;
  }
  while (static_cast<double>(sample.utime - intervalStart_) >= interval_ * 1e6) {
    row();
    intervalStart_ += static_cast<std::int64_t>(interval_ * 1e6);
  }
  ++scans_;
  sumMs_ += sample.milliseconds;
  maxMs_ = sample.milliseconds > maxMs_ ? sample.milliseconds : maxMs_;
  last_ = sample;
}

void DriveReport::finish() {
  if (scans_ > 0) {
    row();
  }
}

void DriveReport::row() {
  ++index_;
  std::fprintf(out_, "%-9d %7lld %9.1f %9.1f %9.1f %9.1f %11zu\n", index_, static_cast<long long>(scans_),
               scans_ > 0 ? sumMs_ / static_cast<double>(scans_) : 0.0, maxMs_,
               static_cast<double>(last_.mapBytes) / 1e6, static_cast<double>(residentBytes()) / 1e6, last_.cells);
  std::fflush(out_);
  scans_ = 0;
  sumMs_ = 0.0;
  maxMs_ = 0.0;
}

std::size_t residentBytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0, resident = 0;
  if (!(statm >> pages >> resident)) {
    return 0;
  }
  return resident * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

}  // namespace ogf::map_io
