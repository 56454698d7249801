// PoseBuffer: validation on insert, ring storage, and interpolation (lerp + slerp) without extrapolation.
#include <ogf/fusion/pose_buffer.hpp>

#include <cmath>
#include <vector>

namespace ogf::fusion {

PoseBuffer::PoseBuffer(const PoseBufferConfig& config) : config_(config), ring_(config.capacity) {}

PoseInsertResult PoseBuffer::insert(const Pose& pose) {
  PoseInsertResult result;
  const auto reject = [&](PoseRejection why, std::int64_t& counter) {
    ++counter;
    result.rejection = why;
    return result;
  };
  switch (contentRejection(pose)) {
    case PoseRejection::kNonFinite:
      return reject(PoseRejection::kNonFinite, counts_.rejected_non_finite);
    case PoseRejection::kAbsurdPosition:
      return reject(PoseRejection::kAbsurdPosition, counts_.rejected_absurd);
    case PoseRejection::kNotUnitQuaternion:
      return reject(PoseRejection::kNotUnitQuaternion, counts_.rejected_not_unit);
    default:
      break;
  }
  if (size_ > 0 && pose.utime == newest().utime) {
    return reject(PoseRejection::kDuplicateTime, counts_.rejected_duplicate_time);
  }
  if (size_ > 0 && pose.utime < newest().utime) {
    return reject(PoseRejection::kOutOfOrder, counts_.rejected_out_of_order);
  }
  const double norm = pose.orientation.norm();
  Pose stored = pose;
  if (norm != 1.0) {
    stored.orientation.normalize();
    result.normalised = true;
    ++counts_.normalised;
  }
  if (size_ > 0) {
    const Pose& previous = newest();
    result.step_translation_m = (stored.position - previous.position).norm();
    result.step_rotation_rad = previous.orientation.angularDistance(stored.orientation);
    result.jump = result.step_translation_m > config_.jump_translation_m ||
                  result.step_rotation_rad > config_.jump_rotation_rad;
    if (result.jump) {
      ++counts_.jumps;
      splits_.push_back({previous.utime, stored.utime});
    }
  }
  if (size_ == ring_.size()) {
    head_ = (head_ + 1) % ring_.size();
    --size_;
    ++counts_.evicted;
    // A split whose earlier pose is gone lies before the oldest pose: coverage says too old there.
    std::erase_if(splits_, [&](const Split& s) { return size_ == 0 || s.before_utime < oldest().utime; });
  }
  ring_[(head_ + size_) % ring_.size()] = stored;
  ++size_;
  ++counts_.accepted;
  return result;
}

PoseRejection PoseBuffer::contentRejection(const Pose& pose) const {
  if (!pose.position.allFinite() || !pose.orientation.coeffs().allFinite()) return PoseRejection::kNonFinite;
  if ((pose.position.array().abs() > config_.max_abs_position_m).any()) return PoseRejection::kAbsurdPosition;
  if (!(std::abs(pose.orientation.norm() - 1.0) <= config_.quaternion_tolerance)) return PoseRejection::kNotUnitQuaternion;
  return PoseRejection::kNone;
}

void PoseBuffer::clear() {
  head_ = 0;
  size_ = 0;
  splits_.clear();
}

bool PoseBuffer::crossesSplit(std::int64_t begin_utime, std::int64_t end_utime) const {
  // [begin, end] needs the trajectory strictly between the two poses of a split when it starts before the
  // later one and ends after the earlier one.
  for (const Split& s : splits_)
    if (begin_utime < s.after_utime && end_utime > s.before_utime) return true;
  return false;
}

PoseCoverage PoseBuffer::coverageAt(std::int64_t utime) const {
  if (size_ == 0 || utime > newest().utime) return PoseCoverage::kNotYet;
  if (utime < oldest().utime) return PoseCoverage::kTooOld;
  return PoseCoverage::kCovered;
}

PoseCoverage PoseBuffer::coverage(std::int64_t begin_utime, std::int64_t end_utime) const {
  // The stored poses have no gaps in between, so the two ends decide; too old wins because waiting
  // cannot help it.
  // A split after the span's beginning breaks it even before the end is covered: waiting cannot help.
  const PoseCoverage begin = coverageAt(begin_utime);
  if (begin != PoseCoverage::kCovered) return begin;
  if (crossesSplit(begin_utime, end_utime)) return PoseCoverage::kBroken;
  return coverageAt(end_utime);
}

PoseLookup PoseBuffer::interpolate(std::int64_t utime) const {
  PoseLookup lookup;
  lookup.coverage = coverageAt(utime);
  if (!lookup.ok()) return lookup;
  if (!splits_.empty() && crossesSplit(utime, utime)) {
    lookup.coverage = PoseCoverage::kBroken;
    return lookup;
  }
  // First stored pose at or after utime (exists, since utime <= newest).
  std::size_t lo = 0;
  std::size_t hi = size_ - 1;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (at(mid).utime < utime) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const Pose& after = at(lo);
  if (after.utime == utime) {
    lookup.pose = after;
    return lookup;
  }
  const Pose& before = at(lo - 1);  // lo > 0 since utime >= oldest and != at(lo)
  const double alpha =
      static_cast<double>(utime - before.utime) / static_cast<double>(after.utime - before.utime);
  lookup.pose.utime = utime;
  lookup.pose.position = before.position + alpha * (after.position - before.position);
  // Eigen's slerp takes the short arc (it flips the sign of one end when their dot product is negative).
  lookup.pose.orientation = before.orientation.slerp(alpha, after.orientation);
  return lookup;
}

}  // namespace ogf::fusion
