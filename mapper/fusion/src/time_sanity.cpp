// TimeSanity: refuses implausible message times and follows a clock that really jumped.
#include <ogf/fusion/time_sanity.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace ogf::fusion {
namespace {

// Bounds far beyond any use, so that the microsecond arithmetic below can never overflow.
constexpr double kMaxBoundS = 1e9;

std::int64_t toUs(double s) { return static_cast<std::int64_t>(std::llround(s * 1e6)); }

bool validBound(double s) { return s > 0.0 && s <= kMaxBoundS; }

}  // namespace

Status TimeSanityConfig::validate() const {
  if (!validBound(max_ahead_s)) return Error{"max_time_ahead_s must be in (0, 1e9] seconds (got " + std::to_string(max_ahead_s) + ")"};
  if (!validBound(max_behind_s)) return Error{"max_time_behind_s must be in (0, 1e9] seconds (got " + std::to_string(max_behind_s) + ")"};
  if (follow_after < 2 || follow_after > 1000)
    return Error{"clock_jump_messages must be in [2, 1000] (got " + std::to_string(follow_after) + ")"};
  return okStatus();
}

TimeSanity::TimeSanity(const TimeSanityConfig& config)
    : max_ahead_us_(toUs(config.max_ahead_s)),
      max_behind_us_(toUs(config.max_behind_s)),
      follow_after_(config.follow_after) {}

bool TimeSanity::follows(const Mark& from, std::int64_t utime, std::int64_t steady_utime) const {
  // Message times are bounded to [0, 2^62) by the adapters, steady times are a process's clock: no overflow.
  const std::int64_t elapsed = steady_utime > from.steady_utime ? steady_utime - from.steady_utime : 0;
  return utime > from.utime && utime - from.utime <= elapsed + max_ahead_us_;
}

std::optional<std::int64_t> TimeSanity::expectedAt(std::int64_t steady_utime) const {
  if (!reference_) return std::nullopt;
  return *reference_ + std::max<std::int64_t>(0, steady_utime - reference_steady_);
}

TimeVerdict TimeSanity::check(std::int64_t utime, std::int64_t wall_utime, std::int64_t steady_utime) {
  TimeVerdict verdict = TimeVerdict::kAccept;
  if (!reference_) {
    if (utime > wall_utime && utime - wall_utime > max_ahead_us_) verdict = TimeVerdict::kAheadOfHost;
  } else if (utime > *reference_ && !follows({*reference_, reference_steady_}, utime, steady_utime)) {
    verdict = TimeVerdict::kAheadOfStream;
  } else if (utime < *reference_ && *reference_ - utime > max_behind_us_) {
    verdict = TimeVerdict::kBehindStream;
  }
  if (verdict == TimeVerdict::kAccept) {
    candidates_ = 0;
    if (!reference_) {
      reference_ = utime;
      reference_steady_ = steady_utime;
    } else if (utime > *reference_) {
      // The reference's steady time moves on by at most the message time's advance: a message that
      // advances less than the host time elapsed (a partial scan the driver held across a pause and sends
      // late) never shortens the allowance the next messages are measured against.
      reference_steady_ = std::min(steady_utime, reference_steady_ + (utime - *reference_));
      reference_ = utime;
    }
    return verdict;
  }
  // Refused: does it confirm the refused messages before it?
  candidates_ = candidates_ > 0 && follows(last_candidate_, utime, steady_utime) ? candidates_ + 1 : 1;
  last_candidate_ = {utime, steady_utime};
  if (candidates_ >= follow_after_) {
    candidates_ = 0;
    before_jump_ = reference_;
    reference_ = utime;
    reference_steady_ = steady_utime;
    ++counts_.jumps_followed;
    return TimeVerdict::kFollowJump;
  }
  if (verdict == TimeVerdict::kBehindStream) {
    ++counts_.refused_behind;
  } else {
    ++counts_.refused_ahead;
  }
  return verdict;
}

}  // namespace ogf::fusion
