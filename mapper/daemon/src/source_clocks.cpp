// One source's watch over its clock against its robot's odometry: each scan against the newest pose
// (ogf::fusion::ClockAgreement), a warning when they stop agreeing and a note when they agree again, and the
// state in OGF_MAPPER_STATUS.
#include <spdlog/spdlog.h>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/source_intake.hpp"

namespace ogf::mapper_daemon {

void SourceIntake::watchClocks(const ogf::lidar_scan_t& scan) {
  const fusion::ScanClock clock = adapters::scanClockOf(scan, source_.time_base);
  const fusion::ScanClock other = clock == fusion::ScanClock::kDevice ? fusion::ScanClock::kHost : fusion::ScanClock::kDevice;
  fusion::ClockSample sample{clock, adapters::scanStartOn(scan, clock), adapters::scanStartOn(scan, other), std::nullopt};
  // Only odometry that is still arriving says which clock it is on; a silent odometry is another fault.
  sample.newest_pose_utime = robot_.newestFreshPose(steadyUtime(), clocks_.toleranceUs());
  const auto previous = clocks_.state();
  const auto v = clocks_.observe(sample);
  if (!v.changed) return;
  if (v.state == fusion::ClockState::kDisagree) {
    spdlog::warn("{}clocks: {}", label_, clocks_.describe());
  } else if (v.state == fusion::ClockState::kAgree) {
    if (previous == fusion::ClockState::kDisagree) spdlog::warn("{}clocks: agree again: {}", label_, clocks_.describe());
    else spdlog::info("{}clocks: {}", label_, clocks_.describe());
  }
}

void SourceIntake::fillClocks(std::int8_t& clocks, std::int8_t& scan_clock, std::int64_t& offset_us) const {
  switch (clocks_.state()) {
    case fusion::ClockState::kUnknown: clocks = ogf::mapper_status_t::CLOCKS_UNKNOWN; break;
    case fusion::ClockState::kAgree: clocks = ogf::mapper_status_t::CLOCKS_AGREE; break;
    case fusion::ClockState::kDisagree: clocks = ogf::mapper_status_t::CLOCKS_DISAGREE; break;
  }
  offset_us = clocks_.state() == fusion::ClockState::kUnknown ? 0 : clocks_.last().offset_us;
  if (pending_.counts().scans_in == 0) scan_clock = ogf::mapper_status_t::SCAN_CLOCK_NONE;
  else scan_clock = clocks_.lastSample().clock == fusion::ScanClock::kDevice ? ogf::mapper_status_t::SCAN_CLOCK_DEVICE
                                                                           : ogf::mapper_status_t::SCAN_CLOCK_HOST;
}

}  // namespace ogf::mapper_daemon
