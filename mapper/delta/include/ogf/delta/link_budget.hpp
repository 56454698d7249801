// The bytes per second one delta channel may carry (deltas.max_bytes_per_s): a token bucket. Bytes accrue
// at the rate, up to `burst_s` seconds of them; what is sent is spent, keyframes included, and may take the
// bucket below zero (a keyframe part, an update's first message, go out whole), which later updates then
// repay. Time is whatever clock the caller passes (steady microseconds in ogf-mapper).
#pragma once

#include <cstdint>

namespace ogf::delta {

class LinkBudget {
 public:
  // bytes_per_s <= 0: unbounded (allowance() is kUnbounded, spending is only counted).
  LinkBudget(double bytes_per_s, double burst_s, std::int64_t now_us);

  static constexpr std::int64_t kUnbounded = -1;

  bool bounded() const { return rate_ > 0; }
  // Adds the bytes accrued since the last call (a clock going back adds nothing).
  void refill(std::int64_t now_us);
  // Bytes that may go out now: the bucket's content, 0 when it is in debt; kUnbounded when not bounded.
  std::int64_t allowance() const;
  void spend(std::int64_t bytes);
  // Microseconds until the bucket is out of debt at the rate (0 when it is, or when unbounded): a paced
  // sender waits this long before its next message.
  std::int64_t debtUs() const;
  // Bytes spent since construction.
  std::int64_t spent() const { return spent_; }

 private:
  double rate_;
  double capacity_;
  double tokens_;
  std::int64_t last_us_;
  std::int64_t spent_ = 0;
};

}  // namespace ogf::delta
