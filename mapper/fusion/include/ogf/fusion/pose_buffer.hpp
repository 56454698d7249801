// The recent odometry of the robot body, validated on the way in, and the pose at any instant it covers:
// linear interpolation of position and slerp of orientation between the two poses around that instant.
// It never extrapolates: an instant after the newest pose is "not yet covered" (wait for odometry), one
// before the oldest pose kept is "too old" (it will never be covered). Poses are rejected and counted when
// out of order, at a duplicate time, NaN/Inf, farther from the origin than any place a map can hold, or
// with a quaternion whose norm is off by more than the tolerance (within it they are normalised). A step
// larger than max_pose_jump splits the trajectory: the pose is kept, but nothing is interpolated across the
// step (an instant or a span crossing it is "broken"), since the odometry did not say where the robot was
// in between. Capacity is fixed; the oldest pose is evicted.
#pragma once

#include <ogf/fusion/fusion_config.hpp>
#include <ogf/fusion/pose.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ogf::fusion {

enum class PoseRejection { kNone, kOutOfOrder, kDuplicateTime, kNonFinite, kNotUnitQuaternion, kAbsurdPosition };

struct PoseInsertResult {
  PoseRejection rejection = PoseRejection::kNone;
  bool normalised = false;  // accepted after normalising a quaternion within tolerance
  bool jump = false;        // accepted, but the step from the previous pose exceeds max_pose_jump: a split
  double step_translation_m = 0.0;  // step from the previous pose (0 for the first)
  double step_rotation_rad = 0.0;

  bool accepted() const { return rejection == PoseRejection::kNone; }
};

struct PoseBufferCounts {
  std::int64_t accepted = 0;
  std::int64_t rejected_out_of_order = 0;
  std::int64_t rejected_duplicate_time = 0;
  std::int64_t rejected_non_finite = 0;
  std::int64_t rejected_not_unit = 0;
  std::int64_t rejected_absurd = 0;
  std::int64_t normalised = 0;
  std::int64_t jumps = 0;
  std::int64_t evicted = 0;

  std::int64_t rejected() const {
    return rejected_out_of_order + rejected_duplicate_time + rejected_non_finite + rejected_not_unit +
           rejected_absurd;
  }
};

enum class PoseCoverage {
  kCovered,     // between the oldest and the newest pose kept (inclusive)
  kNotYet,      // after the newest pose, or no pose yet: wait for odometry
  kTooOld,      // before the oldest pose kept: will never be covered
  kBroken,      // crosses a split of the trajectory (a step beyond max_pose_jump): will never be covered
};

struct PoseLookup {
  PoseCoverage coverage = PoseCoverage::kNotYet;
  Pose pose;  // valid when coverage == kCovered

  bool ok() const { return coverage == PoseCoverage::kCovered; }
};

class PoseBuffer {
 public:
  // config must validate (PoseBufferConfig::validate).
  explicit PoseBuffer(const PoseBufferConfig& config);

  PoseInsertResult insert(const Pose& pose);
  // What insert() would refuse in the pose itself, whatever its time (non-finite, absurd, not a unit
  // quaternion), or kNone; counts nothing.
  PoseRejection contentRejection(const Pose& pose) const;
  // Forgets every pose (the odometry's clock jumped: the times kept are on another clock).
  void clear();

  // The pose at utime: exact at a stored pose, interpolated between two, never extrapolated.
  PoseLookup interpolate(std::int64_t utime) const;
  // Whether every instant in [begin_utime, end_utime] is covered (begin <= end).
  PoseCoverage coverage(std::int64_t begin_utime, std::int64_t end_utime) const;

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const Pose& oldest() const { return at(0); }  // precondition: !empty()
  const Pose& newest() const { return at(size_ - 1); }
  const PoseBufferCounts& counts() const { return counts_; }

 private:
  // No modulo: a 64-bit division per access made the binary search of interpolate() its main cost.
  const Pose& at(std::size_t i) const {
    const std::size_t j = head_ + i;
    return ring_[j >= ring_.size() ? j - ring_.size() : j];
  }
  PoseCoverage coverageAt(std::int64_t utime) const;
  bool crossesSplit(std::int64_t begin_utime, std::int64_t end_utime) const;

  // The time of the last pose before a split and of the first after it.
  struct Split {
    std::int64_t before_utime;
    std::int64_t after_utime;
  };

  PoseBufferConfig config_;
  std::vector<Pose> ring_;  // capacity slots, [head_, head_ + size_) in use, oldest first
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::vector<Split> splits_;  // oldest first; those before the oldest pose kept are dropped
  PoseBufferCounts counts_;
};

}  // namespace ogf::fusion
