// When to ask again for a keyframe of a stream while one is needed. Once the stream has been heard on the
// bus, every `retry`. Before that (no mapper yet, or one that does not publish the stream: OGF_NAV_GRID with
// nav.enabled false), at doubling intervals up to `longest`, so a silent stream costs the bus a request a
// few times a minute rather than every `retry`; the first message heard makes a request due at once.
#pragma once

#include <algorithm>
#include <chrono>

namespace ogf::view {

class KeyframeRetry {
 public:
  using Clock = std::chrono::steady_clock;

  KeyframeRetry(Clock::duration retry, Clock::duration longest)
      : retry_(retry), longest_(std::max(longest, retry)), wait_(retry) {}

  // Whether to ask now (while a keyframe is needed): never asked yet, the stream just heard, or the wait
  // after the last request over.
  bool due(Clock::time_point now) const { return now >= next_; }
  // A request was sent at `now`.
  void asked(Clock::time_point now) {
    next_ = now + wait_;
    if (!heard_) wait_ = std::min(2 * wait_, longest_);
  }
  // A message of the stream arrived. The first one makes a request due at once, and from then on the wait
  // is `retry`.
  void heard() {
    if (heard_) return;
    heard_ = true;
    wait_ = retry_;
    next_ = Clock::time_point::min();
  }

 private:
  Clock::duration retry_;
  Clock::duration longest_;
  Clock::duration wait_;
  Clock::time_point next_ = Clock::time_point::min();
  bool heard_ = false;
};

}  // namespace ogf::view
