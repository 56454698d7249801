// Whether the mapper's inputs arrive: the scans, and the poses when they come from odometry. Scans that
// arrive without odometry (or odometry without scans) map nothing, and without a word the user blames the
// queue or the filter; InputWatch tells the states apart so the daemon can say which input is missing,
// once per change, and put the state in its status. A stream arrives while its last message is at most
// silence_s old; it is silent once nothing came for silence_s, the start counting as a message, so that
// the first message of one stream is not taken for the other's absence. A stream that arrived before is
// missing only when the other went on arriving for silence_s after it fell silent: two streams that stop
// within silence_s of each other (a replay that ends) have both stopped, not one. Pure: times come in as arguments.
#pragma once

#include <cstdint>
#include <optional>

namespace ogf::fusion {

enum class InputState {
  kNone,             // neither input arrives
  kOk,               // scans arrive, and poses when they are needed
  kWaitingForPoses,  // scans arrive, no pose for silence_s
  kWaitingForScans,  // poses arrive (or, with a fixed pose, nothing but scans is needed), no scan for
                     // silence_s
};

const char* inputStateName(InputState s);

struct InputWatchConfig {
  double silence_s = 3.0;    // a stream without a message this long is missing
  bool poses_needed = true;  // false: the pose is fixed (configuration), only scans are needed
};

class InputWatch {
 public:
  InputWatch(const InputWatchConfig& config, std::int64_t start_utime);

  void scanArrived(std::int64_t utime) { last_scan_ = utime; }
  void poseArrived(std::int64_t utime) { last_pose_ = utime; }

  // A state to report: the new one and the one before. Nothing while the state holds, except once at the
  // end of the start's grace when nothing arrived at all (state and previous both kNone).
  struct Change {
    InputState state = InputState::kNone;
    InputState previous = InputState::kNone;
  };
  // Re-evaluates the state at `utime` (the clock of the arrivals, monotonic).
  std::optional<Change> observe(std::int64_t utime);

  InputState state() const { return state_; }
  // Microseconds since the last scan or pose at `utime`; nullopt when none arrived.
  std::optional<std::int64_t> sinceScan(std::int64_t utime) const { return since(last_scan_, utime); }
  std::optional<std::int64_t> sincePose(std::int64_t utime) const { return since(last_pose_, utime); }
  // How long the start, or the last message of the stream now missing, lies before `utime`.
  std::int64_t silentFor(std::int64_t utime) const;
  bool posesNeeded() const { return config_.poses_needed; }

 private:
  static std::optional<std::int64_t> since(std::optional<std::int64_t> last, std::int64_t utime) {
    if (!last) return std::nullopt;
    return utime - *last;
  }
  bool arriving(std::optional<std::int64_t> last, std::int64_t utime) const;
  bool silent(std::optional<std::int64_t> last, std::int64_t utime) const;
  // The stream whose last message was `last` is missing while the other, last heard at other_last, arrives.
  bool missing(std::optional<std::int64_t> last, std::int64_t other_last, std::int64_t utime) const;

  InputWatchConfig config_;
  std::int64_t silence_us_;
  std::int64_t start_;
  std::optional<std::int64_t> last_scan_, last_pose_;
  InputState state_ = InputState::kNone;
  bool announced_ = false;  // the state has been reported (kNone at the start is not, until the grace ends)
};

}  // namespace ogf::fusion
