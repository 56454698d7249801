#include "ogf/log_io/stream_gaps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ogf::log_io {
namespace {

// A silence is a gap when it lasts this many usual intervals, and at least kMinGapUs: the stream's rate
// is learnt from its first intervals.
constexpr double kGapFactor = 3.0;
constexpr std::int64_t kMinGapUs = 250'000;
constexpr std::int64_t kIntervalsToLearn = 3;

}  // namespace

void StreamGaps::add(std::int64_t utime, std::optional<std::int64_t> seq) {
  ++messages_;
  const std::int64_t dt = last_utime_ ? utime - *last_utime_ : 0;
  bool gap = false;
  if (seq && last_seq_) {
    if (*seq > *last_seq_ + 1) {
      missing_ += *seq - *last_seq_ - 1;
      gap = true;
    }
  } else if (last_utime_ && intervals_ >= kIntervalsToLearn && dt >= kMinGapUs &&
             static_cast<double>(dt) > kGapFactor * usual_interval_us_) {
    missing_ += std::max<std::int64_t>(1, std::llround(static_cast<double>(dt) / usual_interval_us_) - 1);
    gap = true;
  }
  if (gap) {
    ++gaps_;
    longest_us_ = std::max(longest_us_, dt);
  } else if (last_utime_ && dt > 0) {
    ++intervals_;
    usual_interval_us_ += (static_cast<double>(dt) - usual_interval_us_) / static_cast<double>(intervals_);
  }
  last_utime_ = utime;
  if (seq) last_seq_ = seq;
}

std::string StreamGaps::summary(const std::string& what) const {
  if (gaps_ == 0) return {};
  return fmt::format("{}: {} missing in {} gap{} (the longest {:.3f} s): {} of {} recorded", what, missing_, gaps_,
                     gaps_ == 1 ? "" : "s", static_cast<double>(longest_us_) / 1e6, messages_, messages_ + missing_);
}

}  // namespace ogf::log_io
