// The scans that wait for the odometry covering them, and the policy that bounds the wait
// (docs/architecture.md, "Frames and time": no pose covering a scan's time → wait a bounded time, then drop
// the scan and count it; never extrapolate silently). Pure: the caller passes the time in. Bounded in scans
// and in points: when a new scan does not fit, the oldest whole scans are dropped, so memory never grows
// without bound. Each drop is counted under its cause: the mapper fell behind only when the poses cover the
// dropped scan (it could have been mapped); a scan still waiting for its poses counts as dropped for want of
// a pose, so missing odometry is never blamed on the queue. A scan leaves by popReady() once the PoseBuffer
// covers its whole span, in arrival order, or by popOldest() when the pose is fixed (no odometry to wait
// for: such scans come in by pushFixedPose(), and one pushed out is dropped behind); it is dropped when it
// has waited longer than max_pose_wait_s, when its span starts before the oldest pose kept (it can never be
// covered), or when it spans a split of the trajectory (an odometry jump beyond max_pose_jump: never
// interpolated across). Payload is whatever the daemon needs to map the scan later (a
// shared_ptr to the decoded message, an index); it is moved in and out.
#pragma once

#include <ogf/fusion/fusion_config.hpp>
#include <ogf/fusion/pose_buffer.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>

namespace ogf::fusion {

// What the policy needs to know of a scan.
struct ScanSpan {
  std::int64_t begin_utime = 0;  // first point's time, microseconds
  std::int64_t end_utime = 0;    // last point's time
  std::size_t points = 0;
};

// Cumulative counters, named as in mapper_status_t.
struct PendingScansCounts {
  std::int64_t scans_in = 0;
  std::int64_t scans_dropped_behind = 0;   // covered by the poses, dropped to make room; or alone too large
  std::int64_t scans_dropped_no_pose = 0;  // waited too long, older than the oldest pose kept, or dropped to
                                           // make room while its poses had not arrived
  std::int64_t scans_late = 0;             // arrived after a newer scan (span begins no later)
  std::int64_t scans_rejected = 0;         // malformed span (end before begin)
  std::int64_t scans_dropped_pose_jump = 0;  // spans a split of the trajectory

  // Sums the counts of several queues (one per source of scans).
  PendingScansCounts& operator+=(const PendingScansCounts& o) {
    scans_in += o.scans_in;
    scans_dropped_behind += o.scans_dropped_behind;
    scans_dropped_no_pose += o.scans_dropped_no_pose;
    scans_late += o.scans_late;
    scans_rejected += o.scans_rejected;
    scans_dropped_pose_jump += o.scans_dropped_pose_jump;
    return *this;
  }
};

enum class PushOutcome { kQueued, kLate, kRejected, kTooLarge };

template <class Payload>
class PendingScans {
 public:
  struct Entry {
    ScanSpan span;
    std::int64_t arrived_utime = 0;
    Payload payload;
  };

  // config must validate (PendingScansConfig::validate).
  explicit PendingScans(const PendingScansConfig& config)
      : config_(config), max_wait_us_(std::llround(config.max_pose_wait_s * 1e6)) {}

  // Queues a scan that arrived at now_utime (the caller's clock). Drops the oldest whole scans until it
  // fits, each counted by what `poses` says of it (covered: dropped_behind; not yet or never covered:
  // dropped_no_pose; across a split: dropped_pose_jump); a scan larger than max_pending_points alone is
  // dropped and counted as dropped_behind.
  PushOutcome push(const ScanSpan& span, Payload payload, const PoseBuffer& poses, std::int64_t now_utime) {
    const auto coverage = [&](const ScanSpan& s) { return poses.coverage(s.begin_utime, s.end_utime); };
    return pushCounting(span, std::move(payload), coverage, now_utime);
  }
  // The same for a sensor whose pose is fixed (taken by popOldest): no scan waits for a pose, so every scan
  // dropped to make room is dropped for the mapper falling behind.
  PushOutcome pushFixedPose(const ScanSpan& span, Payload payload, std::int64_t now_utime) {
    const auto coverage = [](const ScanSpan&) { return PoseCoverage::kCovered; };
    return pushCounting(span, std::move(payload), coverage, now_utime);
  }

  // The oldest scan, when the poses cover its span; nothing while it still waits. Scans that can no longer
  // be covered, or have waited longer than max_pose_wait_s, are dropped on the way. The scan stays queued
  // (popFront() takes it), so a caller with several queues can map the oldest of their ready scans first.
  const Entry* readyFront(const PoseBuffer& poses, std::int64_t now_utime) {
    while (!queue_.empty()) {
      Entry& front = queue_.front();
      const PoseCoverage c = poses.coverage(front.span.begin_utime, front.span.end_utime);
      if (c == PoseCoverage::kCovered) return &front;
      if (c == PoseCoverage::kBroken) {
        dropFront(counts_.scans_dropped_pose_jump);
        continue;
      }
      if (c == PoseCoverage::kTooOld || now_utime - front.arrived_utime > max_wait_us_) {
        dropFront(counts_.scans_dropped_no_pose);
        continue;
      }
      return nullptr;  // still waiting; later scans wait behind it to keep arrival order
    }
    return nullptr;
  }

  // The oldest scan whatever the poses, for a sensor whose pose is fixed (nothing to wait for).
  const Entry* oldest() const { return queue_.empty() ? nullptr : &queue_.front(); }

  // Takes the oldest scan out; the queue must not be empty.
  Entry popFront() {
    Entry front(std::move(queue_.front()));
    points_ -= front.span.points;
    queue_.pop_front();
    return front;
  }

  // readyFront() and popFront() in one step.
  std::optional<Entry> popReady(const PoseBuffer& poses, std::int64_t now_utime) {
    if (readyFront(poses, now_utime) == nullptr) return std::nullopt;
    return popFront();
  }

  // oldest() and popFront() in one step.
  std::optional<Entry> popOldest() {
    if (queue_.empty()) return std::nullopt;
    return popFront();
  }

  // The scans' clock jumped (TimeSanity followed it): a scan is late only against scans on the new clock.
  void restartClock() { last_begin_utime_.reset(); }

  std::size_t size() const { return queue_.size(); }
  std::size_t points() const { return points_; }
  const PendingScansCounts& counts() const { return counts_; }

 private:
  // push(), with `coverage` telling what the poses say of a queued scan's span.
  template <class Coverage>
  PushOutcome pushCounting(const ScanSpan& span, Payload payload, Coverage coverage, std::int64_t now_utime) {
    ++counts_.scans_in;
    if (span.end_utime < span.begin_utime) {
      ++counts_.scans_rejected;
      return PushOutcome::kRejected;
    }
    if (last_begin_utime_ && span.begin_utime <= *last_begin_utime_) {
      ++counts_.scans_late;
      return PushOutcome::kLate;
    }
    last_begin_utime_ = span.begin_utime;
    if (span.points > config_.max_pending_points) {
      ++counts_.scans_dropped_behind;
      return PushOutcome::kTooLarge;
    }
    while (!queue_.empty() &&
           (queue_.size() >= config_.max_pending_scans || points_ + span.points > config_.max_pending_points)) {
      dropFront(counterFor(coverage(queue_.front().span)));
    }
    points_ += span.points;
    queue_.push_back(Entry{span, now_utime, std::move(payload)});
    return PushOutcome::kQueued;
  }

  std::int64_t& counterFor(PoseCoverage coverage) {
    switch (coverage) {
      case PoseCoverage::kCovered: return counts_.scans_dropped_behind;
      case PoseCoverage::kBroken: return counts_.scans_dropped_pose_jump;
      case PoseCoverage::kNotYet:
      case PoseCoverage::kTooOld: break;
    }
    return counts_.scans_dropped_no_pose;
  }

  void dropFront(std::int64_t& counter) {
    points_ -= queue_.front().span.points;
    queue_.pop_front();
    ++counter;
  }

  PendingScansConfig config_;
  std::int64_t max_wait_us_;
  std::deque<Entry> queue_;
  std::size_t points_ = 0;
  std::optional<std::int64_t> last_begin_utime_;
  PendingScansCounts counts_;
};

}  // namespace ogf::fusion
