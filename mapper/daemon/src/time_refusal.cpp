// The log of TimeSanity's verdicts (time_refusal.hpp).
#include "time_refusal.hpp"

#include <spdlog/spdlog.h>

namespace ogf::mapper_daemon {
namespace {

// Seconds between two microsecond times, for the log.
double secondsBetween(std::int64_t later, std::int64_t earlier) { return static_cast<double>(later - earlier) * 1e-6; }

}  // namespace

bool timePlausible(const std::string& what, fusion::TimeVerdict verdict, const fusion::TimeSanity& clock,
                   std::optional<std::int64_t> expected, std::int64_t utime, std::int64_t wall_utime,
                   transport::LogRateLimiter& log) {
  using fusion::TimeVerdict;
  if (verdict == TimeVerdict::kAccept) return true;
  if (verdict == TimeVerdict::kFollowJump) {
    spdlog::warn("{} clock jumped from {} to {} (host clock {}): followed after consistent messages", what,
                 clock.timeBeforeLastJump() ? std::to_string(*clock.timeBeforeLastJump()) : "none", utime, wall_utime);
    return true;
  }
  const auto n = log.allow();
  if (!n) return false;
  const double max_ahead_s = static_cast<double>(clock.maxAheadUs()) * 1e-6;
  std::string why;
  if (verdict == TimeVerdict::kAheadOfHost) {
    why = fmt::format("{:.3f} s ahead of the host clock {} (at most {} s is plausible)", secondsBetween(utime, wall_utime),
                      wall_utime, max_ahead_s);
  } else if (verdict == TimeVerdict::kAheadOfStream && expected) {
    why = fmt::format("{:.3f} s ahead of the stream, which is expected at {} (its newest time {} plus the host time "
                      "since; at most {} s beyond is plausible)",
                      secondsBetween(utime, *expected), *expected, clock.reference().value_or(0), max_ahead_s);
  } else {
    why = fmt::format("{:.3f} s behind the stream's newest time {} (at most {} s is plausible)",
                      secondsBetween(clock.reference().value_or(utime), utime), clock.reference().value_or(0),
                      static_cast<double>(clock.maxBehindUs()) * 1e-6);
  }
  spdlog::warn("{} at {} refused: {}; host clock {} ({} more)", what, utime, why, wall_utime, *n);
  return false;
}

}  // namespace ogf::mapper_daemon
