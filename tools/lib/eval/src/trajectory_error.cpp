// Absolute trajectory error: estimated positions against the true trajectory at the same stamps.
#include "ogf/eval/trajectory_error.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace ogf::eval {

namespace {

// The true position at `utime`: exact sample, or linear interpolation across a gap of at most `max_gap`.
std::optional<Eigen::Vector3d> truePositionAt(const std::vector<sim::StampedPose>& truth, std::int64_t utime,
                                              std::int64_t max_gap) {
  const auto after = std::lower_bound(truth.begin(), truth.end(), utime,
                                      [](const sim::StampedPose& p, std::int64_t t) { return p.utime < t; });
  if (after == truth.end()) return std::nullopt;
  if (after->utime == utime) return after->pose.position;
  if (after == truth.begin()) return std::nullopt;
  const auto before = after - 1;
  const std::int64_t gap = after->utime - before->utime;
  if (gap > max_gap) return std::nullopt;
  const double s = static_cast<double>(utime - before->utime) / static_cast<double>(gap);
  return before->pose.position + s * (after->pose.position - before->pose.position);
}

}  // namespace

TrajectoryError absoluteTrajectoryError(const std::vector<sim::StampedPose>& truth,
                                        const std::vector<sim::StampedPose>& estimate,
                                        std::int64_t max_truth_gap_us) {
  TrajectoryError e;
  double sum = 0.0;
  double sum_sq = 0.0;
  for (const auto& p : estimate) {
    const auto true_position = truePositionAt(truth, p.utime, max_truth_gap_us);
    if (!true_position) {
      ++e.unmatched;
      continue;
    }
    const double d = (p.pose.position - *true_position).norm();
    sum += d;
    sum_sq += d * d;
    e.max_m = std::max(e.max_m, d);
    ++e.matched;
  }
  if (e.matched > 0) {
    e.mean_m = sum / static_cast<double>(e.matched);
    e.rmse_m = std::sqrt(sum_sq / static_cast<double>(e.matched));
  }
  return e;
}

}  // namespace ogf::eval
