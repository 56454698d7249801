#include "ogf/map_io/odometry_clock.hpp"

#include <algorithm>

namespace ogf::map_io {

std::optional<fusion::ClockAgreement> clockMismatch(const ScanRecord& scan, TimeBase base,
                                                    const fusion::PoseBuffer& poses) {
  if (poses.empty()) return std::nullopt;
  const fusion::ScanClock clock = scan.clock(base);
  const fusion::ScanClock other = clock == fusion::ScanClock::kDevice ? fusion::ScanClock::kHost : fusion::ScanClock::kDevice;
  const std::int64_t t = scan.startOn(clock);
  fusion::ClockAgreement agreement;
  const auto verdict =
      agreement.observe({clock, t, scan.startOn(other), std::clamp(t, poses.oldest().utime, poses.newest().utime)});
  if (verdict.state != fusion::ClockState::kDisagree) return std::nullopt;
  return agreement;
}

}  // namespace ogf::map_io
