// ogf-mapper's watch over its two clocks: each scan against the newest pose (ogf::fusion::ClockAgreement),
// a warning when they stop agreeing and a note when they agree again, and the state in OGF_MAPPER_STATUS.
#include <spdlog/spdlog.h>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/scan_intake.hpp"

namespace ogf::mapper_daemon {

void ScanIntake::watchClocks(const ogf::lidar_scan_t& scan) {
  const fusion::ScanClock clock = adapters::scanClockOf(scan, options_.time_base);
  const fusion::ScanClock other = clock == fusion::ScanClock::kDevice ? fusion::ScanClock::kHost : fusion::ScanClock::kDevice;
  fusion::ClockSample sample{clock, adapters::scanStartOn(scan, clock), adapters::scanStartOn(scan, other), std::nullopt};
  // Only odometry that is still arriving says which clock it is on; a silent odometry is another fault.
  if (!poses_.empty() && last_pose_steady_ != 0 && steadyUtime() - last_pose_steady_ <= clocks_.toleranceUs())
    sample.newest_pose_utime = poses_.newest().utime;
  const auto previous = clocks_.state();
  const auto v = clocks_.observe(sample);
  if (!v.changed) return;
  if (v.state == fusion::ClockState::kDisagree) {
    spdlog::warn("clocks: {}", clocks_.describe());
  } else if (v.state == fusion::ClockState::kAgree) {
    if (previous == fusion::ClockState::kDisagree) spdlog::warn("clocks: agree again: {}", clocks_.describe());
    else spdlog::info("clocks: {}", clocks_.describe());
  }
}

void ScanIntake::fillClockStatus(ogf::mapper_status_t& s) const {
  switch (clocks_.state()) {
    case fusion::ClockState::kUnknown: s.clocks = ogf::mapper_status_t::CLOCKS_UNKNOWN; break;
    case fusion::ClockState::kAgree: s.clocks = ogf::mapper_status_t::CLOCKS_AGREE; break;
    case fusion::ClockState::kDisagree: s.clocks = ogf::mapper_status_t::CLOCKS_DISAGREE; break;
  }
  s.clock_offset_us = clocks_.state() == fusion::ClockState::kUnknown ? 0 : clocks_.last().offset_us;
  if (pending_.counts().scans_in == 0) s.scan_clock = ogf::mapper_status_t::SCAN_CLOCK_NONE;
  else s.scan_clock = clocks_.lastSample().clock == fusion::ScanClock::kDevice ? ogf::mapper_status_t::SCAN_CLOCK_DEVICE
                                                                            : ogf::mapper_status_t::SCAN_CLOCK_HOST;
}

}  // namespace ogf::mapper_daemon
