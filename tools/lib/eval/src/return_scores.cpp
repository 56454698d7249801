// How a map holds its own returns: see return_scores.hpp.
#include "ogf/eval/return_scores.hpp"

namespace ogf::eval {

void ReturnScorer::add(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, const Estimate& estimate) {
  const double range = (endpoint - origin).norm();
  if (!(range >= from_ && range <= to_)) return;
  ++returns_;
  const CellEstimate end = estimate(cellKeyOf(endpoint, resolution_));
  occupied_ += end.cell_class > 0 ? 1 : 0;
  free_ += end.cell_class < 0 ? 1 : 0;
  const Eigen::Vector3d halfway = 0.5 * (origin + endpoint);
  halfway_free_ += estimate(cellKeyOf(halfway, resolution_)).cell_class < 0 ? 1 : 0;
}

ReturnScores ReturnScorer::scores() const {
  ReturnScores s;
  s.returns = returns_;
  if (returns_ == 0) return s;
  const auto n = static_cast<double>(returns_);
  s.occupied = static_cast<double>(occupied_) / n;
  s.free = static_cast<double>(free_) / n;
  s.unknown = static_cast<double>(returns_ - occupied_ - free_) / n;
  s.halfway_free = static_cast<double>(halfway_free_) / n;
  return s;
}

}  // namespace ogf::eval
