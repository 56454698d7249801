#include "ogf/fusion/clock_agreement.hpp"

#include <cstdio>
#include <cstdlib>
#include <ctime>

namespace ogf::fusion {

const char* clockName(ScanClock c) { return c == ScanClock::kDevice ? "device" : "host"; }

ClockVerdict ClockAgreement::observe(const ClockSample& sample) {
  ClockVerdict v;
  if (sample.newest_pose_utime) {
    v.offset_us = sample.scan_utime - *sample.newest_pose_utime;
    v.other_offset_us = sample.other_scan_utime - *sample.newest_pose_utime;
    v.state = std::llabs(v.offset_us) <= tolerance_us_ ? ClockState::kAgree : ClockState::kDisagree;
  }
  v.changed = v.state != state_;
  state_ = v.state;
  last_ = v;
  sample_ = sample;
  return v;
}

std::string isoUtc(std::int64_t utime) {
  const std::time_t secs = static_cast<std::time_t>(utime / 1'000'000 - (utime % 1'000'000 < 0 ? 1 : 0));
  const auto ms = static_cast<int>(((utime % 1'000'000) + 1'000'000) % 1'000'000 / 1000);
  std::tm tm{};
  if (gmtime_r(&secs, &tm) == nullptr) return std::to_string(utime) + " us";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, ms);
  return buf;
}

namespace {

std::string seconds(std::int64_t us) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%+.3f s", static_cast<double>(us) / 1e6);
  return buf;
}

}  // namespace

std::string ClockAgreement::describe(std::string_view time_flag) const {
  const ScanClock used = sample_.clock;
  const ScanClock other = used == ScanClock::kDevice ? ScanClock::kHost : ScanClock::kDevice;
  if (state_ == ClockState::kUnknown) return "no odometry to compare the scans with";
  const std::string times = std::string("scan at ") + isoUtc(sample_.scan_utime) + " on the " + clockName(used) +
                            " clock (" + isoUtc(sample_.other_scan_utime) + " on the " + clockName(other) +
                            " clock), odometry at " + isoUtc(*sample_.newest_pose_utime) + ", offset " +
                            seconds(last_.offset_us);
  if (state_ == ClockState::kAgree)
    return "scans and odometry agree on the " + std::string(clockName(used)) + " clock: " + times;
  std::string fix;
  if (std::llabs(last_.other_offset_us) <= tolerance_us_) {
    fix = std::string("the odometry is on the ") + clockName(other) + " clock (offset " + seconds(last_.other_offset_us) +
          "): set time_base: " + clockName(other) + " (" + std::string(time_flag) + " " + clockName(other) + ")";
  } else {
    fix = "the odometry matches neither clock (" + std::string(clockName(other)) + " offset " +
          seconds(last_.other_offset_us) +
          "): stamp it with the driver host's clock (CLOCK_REALTIME, or one synchronised to it) and set time_base: "
          "host (" + std::string(time_flag) + " host), or with UTC when the sensor's PPS is locked and time_base: device (" +
          std::string(time_flag) + " device)";
  }
  return "scans and odometry are on different clocks, no scan can be placed: " + times + "; " + fix;
}

}  // namespace ogf::fusion
