// Pacing of a replay: see replay_clock.hpp.
#include "ogf/replay/replay_clock.hpp"

#include <algorithm>
#include <cmath>

namespace ogf::replay {

ReplayClock::ReplayClock(PacingConfig config) : config_(config) {}

std::int64_t ReplayClock::paced(std::int64_t capture_utime) const {
  if (config_.speed <= 0.0 || !origin_) return loop_offset_us_;
  const double since = static_cast<double>(capture_utime - *origin_);
  return loop_offset_us_ + static_cast<std::int64_t>(std::llround(since / config_.speed));
}

std::int64_t ReplayClock::duePacket(std::int64_t capture_utime) {
  if (!origin_) {
    origin_ = capture_utime;
    latest_capture_ = capture_utime;
  }
  latest_capture_ = std::max(latest_capture_, capture_utime);
  std::int64_t due = paced(latest_capture_);
  if (config_.max_rate > 0.0 && any_packet_) {
    const auto spacing = static_cast<std::int64_t>(std::llround(1e6 / config_.max_rate));
    due = std::max(due, last_due_ + spacing);
  }
  due = std::max(due, last_due_);
  last_due_ = due;
  any_packet_ = true;
  return due;
}

std::int64_t ReplayClock::dueEvent(std::int64_t capture_utime) const {
  if (!origin_) return loop_offset_us_;
  return std::max<std::int64_t>(paced(capture_utime), loop_offset_us_);
}

void ReplayClock::nextLoop(std::int64_t gap_us) {
  loop_offset_us_ = last_due_ + std::max<std::int64_t>(gap_us, 0);
  last_due_ = loop_offset_us_;
  if (origin_) latest_capture_ = *origin_;
}

}  // namespace ogf::replay
