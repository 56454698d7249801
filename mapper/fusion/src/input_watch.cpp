// InputWatch: which of the mapper's inputs arrive, and when that changes.
#include <algorithm>
#include <cmath>
#include <ogf/fusion/input_watch.hpp>

namespace ogf::fusion {

const char* inputStateName(InputState s) {
  switch (s) {
    case InputState::kNone:
      return "no input";
    case InputState::kOk:
      return "ok";
    case InputState::kWaitingForPoses:
      return "waiting for poses";
    case InputState::kWaitingForScans:
      return "waiting for scans";
  }
  return "?";
}

InputWatch::InputWatch(const InputWatchConfig& config, std::int64_t start_utime)
    : config_(config), silence_us_(std::llround(config.silence_s * 1e6)), start_(start_utime) {}

bool InputWatch::arriving(std::optional<std::int64_t> last, std::int64_t utime) const {
  return last && utime - *last <= silence_us_;
}

bool InputWatch::silent(std::optional<std::int64_t> last, std::int64_t utime) const {
  return utime - std::max(last.value_or(start_), start_) > silence_us_;
}

bool InputWatch::missing(std::optional<std::int64_t> last, std::int64_t other_last,
                         std::int64_t utime) const {
  // Never arrived: missing once silence_s has passed since the start. Arrived before: missing only when the
  // other stream went on for silence_s after its last message, not when both stop a moment apart (a replay
  // that ends, a robot that shuts down).
  return last ? silent(last, other_last) : silent(last, utime);
}

std::int64_t InputWatch::silentFor(std::int64_t utime) const {
  std::optional<std::int64_t> missing;
  if (state_ == InputState::kWaitingForPoses)
    missing = last_pose_;
  else if (state_ == InputState::kWaitingForScans)
    missing = last_scan_;
  else if (state_ == InputState::kNone)
    missing = std::max(last_scan_.value_or(start_), last_pose_.value_or(start_));
  return utime - std::max(missing.value_or(start_), start_);
}

std::optional<InputWatch::Change> InputWatch::observe(std::int64_t utime) {
  const bool scans = arriving(last_scan_, utime);
  const bool poses = arriving(last_pose_, utime);
  InputState next = state_;
  if (!config_.poses_needed) {
    if (scans)
      next = InputState::kOk;
    else if (silent(last_scan_, utime))
      next = InputState::kWaitingForScans;
  } else if (scans && poses) {
    next = InputState::kOk;
  } else if (scans && missing(last_pose_, *last_scan_, utime)) {
    next = InputState::kWaitingForPoses;
  } else if (poses && missing(last_scan_, *last_pose_, utime)) {
    next = InputState::kWaitingForScans;
  } else if (!scans && !poses) {
    next = InputState::kNone;
  }
  // Otherwise one stream has just begun and the other may still come (the start's grace): no verdict yet.
  if (next != state_) {
    const Change change{next, state_};
    state_ = next;
    announced_ = true;
    return change;
  }
  if (!announced_ && !scans && !poses && utime - start_ > silence_us_) {
    announced_ = true;
    return Change{state_, state_};
  }
  return std::nullopt;
}

}  // namespace ogf::fusion
