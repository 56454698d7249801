// Whether a message's time is plausible for the stream it joins (the odometry, or the scans), so that one
// message with a wrong date can never become the reference every later message is measured against.
// A message is refused when it lies more than max_ahead_s ahead of the host clock (while the stream has
// no reference yet) or of the stream (the newest accepted time plus the host time elapsed since), or more
// than max_behind_s behind the newest accepted time. An accepted message never shortens that allowance:
// one that advances the stream by less than the host time elapsed (a partial scan held across a pause of
// the sensor and published late, dated before the pause) becomes the newest time, but the host time is
// still counted from when the stream's clock was last seen running at host pace, so the scans that resume
// after the pause are on time. Past times are plausible before a reference exists:
// a replayed log is always in the past. A clock that really jumps (a sensor reset, GPS lock gained, a log
// played again) is followed once `follow_after` refused messages in a row agree with each other (each
// within max_ahead_s of what the one before it predicts, and increasing): the last of them becomes the new
// reference. Pure: the caller passes both clocks in.
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>
#include <optional>

namespace ogf::fusion {

struct TimeSanityConfig {
  double max_ahead_s = 10.0;   // ahead of the host clock or of the stream: refused
  double max_behind_s = 10.0;  // behind the newest accepted time: refused (less is left to the buffers)
  int follow_after = 5;        // refused messages in a row that agree with each other: a real clock jump

  Status validate() const;
};

enum class TimeVerdict {
  kAccept,         // plausible (may still be out of order for the buffer that receives it)
  kAheadOfHost,    // no reference yet, and ahead of the host clock
  kAheadOfStream,  // ahead of the newest accepted time plus the host time elapsed since
  kBehindStream,   // behind the newest accepted time by more than max_behind_s
  kFollowJump,     // the clock jumped and this message confirms it: it is the new reference
};

struct TimeSanityCounts {
  std::int64_t refused_ahead = 0;
  std::int64_t refused_behind = 0;
  std::int64_t jumps_followed = 0;

  std::int64_t refused() const { return refused_ahead + refused_behind; }
};

class TimeSanity {
 public:
  // config must validate.
  explicit TimeSanity(const TimeSanityConfig& config);

  // Judges a message dated `utime` arriving at host time `wall_utime` (the system clock) and
  // `steady_utime` (a monotonic clock). kAccept and kFollowJump make it the reference when it is newer.
  TimeVerdict check(std::int64_t utime, std::int64_t wall_utime, std::int64_t steady_utime);

  // The newest accepted time (nullopt before the first), and the time it replaced at the last jump.
  std::optional<std::int64_t> reference() const { return reference_; }
  // Where the stream's clock is expected at `steady_utime`: the newest accepted time plus the host time
  // counted since (nullopt before the first). A message up to max_ahead_s beyond it is plausible.
  std::optional<std::int64_t> expectedAt(std::int64_t steady_utime) const;
  std::int64_t maxAheadUs() const { return max_ahead_us_; }
  std::int64_t maxBehindUs() const { return max_behind_us_; }
  std::optional<std::int64_t> timeBeforeLastJump() const { return before_jump_; }
  const TimeSanityCounts& counts() const { return counts_; }

 private:
  struct Mark {
    std::int64_t utime = 0;
    std::int64_t steady_utime = 0;
  };
  bool follows(const Mark& from, std::int64_t utime, std::int64_t steady_utime) const;

  std::int64_t max_ahead_us_;
  std::int64_t max_behind_us_;
  int follow_after_;
  std::optional<std::int64_t> reference_;
  std::int64_t reference_steady_ = 0;
  std::optional<std::int64_t> before_jump_;
  Mark last_candidate_;
  int candidates_ = 0;  // refused messages in a row that agree with each other
  TimeSanityCounts counts_;
};

}  // namespace ogf::fusion
