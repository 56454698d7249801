// When each record of a replayed capture is due, as an offset from the start of the replay: the capture
// time since the first record divided by the speed factor (0 = as fast as possible), never earlier than a
// packet-rate limit allows, and loop k starting where loop k-1 ended. Pure arithmetic on microseconds, so
// the program can sleep_until(start + due) on a steady clock and never accumulate drift.
#pragma once

#include <cstdint>
#include <optional>

namespace ogf::replay {

struct PacingConfig {
  double speed = 1.0;    // capture time / speed; 0 = no pacing by the capture clock
  double max_rate = 0.0;  // packets per second at most; 0 = no limit
};

class ReplayClock {
 public:
  explicit ReplayClock(PacingConfig config);

  // Offset (µs since the replay's start) at which a packet captured at `capture_utime` is due. Packets
  // must be offered in capture order within a loop; a capture clock that steps back is held at the latest
  // time seen (the packet is sent at once rather than waited for in the past).
  std::int64_t duePacket(std::int64_t capture_utime);
  // Offset at which an event of the same clock that is not a packet (an odometry pose) is due: the capture
  // pacing alone, without the rate limit and without counting as a packet.
  std::int64_t dueEvent(std::int64_t capture_utime) const;
  // Fixes the capture time that maps to offset 0 (the earliest of the first packet and the first pose);
  // without it the first packet offered sets it.
  void setOrigin(std::int64_t capture_utime) { origin_ = capture_utime; latest_capture_ = capture_utime; }
  // Starts the next loop: its first record is due right after the last one of this loop (plus `gap_us`).
  void nextLoop(std::int64_t gap_us);

  // The capture time the replay started from (the first packet or event seen), if any.
  std::optional<std::int64_t> origin() const { return origin_; }

 private:
  std::int64_t paced(std::int64_t capture_utime) const;

  PacingConfig config_;
  std::optional<std::int64_t> origin_;  // capture time of loop 0's first record
  std::int64_t loop_offset_us_ = 0;      // replay offset at which this loop's capture time origin_ falls
  std::int64_t latest_capture_ = 0;      // within this loop
  std::int64_t last_due_ = 0;            // due offset of the last packet
  bool any_packet_ = false;
};

}  // namespace ogf::replay
