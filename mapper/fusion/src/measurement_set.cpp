// MeasurementSet: the range rules of Sun et al. Sec. VI-B applied ray by ray, marks in CellMarks.
#include <ogf/fusion/measurement_set.hpp>

#include <ogf/fusion/ray_caster.hpp>

#include <cassert>

namespace ogf::fusion {

MeasurementSet::MeasurementSet(const MeasurementConfig& config)
    : config_(config), coordinate_limit_m_(config.resolution_m * 1073741824.0) {}

bool MeasurementSet::acceptable(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  if (!a.allFinite() || !b.allFinite()) {
    ++counts_.rejected_non_finite;
    return false;
  }
  // The traversal converts coordinates to int32 cells; 2^30 cells leaves room for max range beyond them.
  if (a.cwiseAbs().maxCoeff() >= coordinate_limit_m_ || b.cwiseAbs().maxCoeff() >= coordinate_limit_m_) {
    ++counts_.rejected_out_of_range;
    return false;
  }
  return true;
}

void MeasurementSet::begin() {
  marks_.clear();
  measurements_.clear();
  counts_ = {};
}

void MeasurementSet::markFreeAlong(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint) {
  marks_.markFree(RayCaster(origin, endpoint, config_.resolution_m));
}

void MeasurementSet::addReturn(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint) {
  if (!acceptable(origin, endpoint)) return;
  const Eigen::Vector3d ray = endpoint - origin;
  const double range = ray.norm();
  if (range < config_.min_range_m) {
    ++counts_.ignored_min_range;
    return;
  }
  if (range > config_.max_range_m) {
    // Cut at max range: the cells up to there are free; the cell holding the cut point is left out, since
    // the traversal excludes its end cell, so nothing beyond max range is ever marked.
    ++counts_.cut_at_max_range;
    markFreeAlong(origin, origin + ray * (config_.max_range_m / range));
    return;
  }
  ++counts_.returns;
  const RayCaster cells(origin, endpoint, config_.resolution_m);
  marks_.markFree(cells);
  marks_.markOccupied(cells.endCell());
}

void MeasurementSet::addNoReturn(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const double length = direction.norm();
  if (!acceptable(origin, Eigen::Vector3d::Zero())) return;
  if (!direction.allFinite() || !(length > 0.0)) {
    ++counts_.rejected_non_finite;
    return;
  }
  if (!config_.free_space_for_no_return) {
    ++counts_.no_return_ignored;
    return;
  }
  ++counts_.no_return_free;
  markFreeAlong(origin, origin + direction * (config_.max_range_m / length));
}

std::span<const Measurement> MeasurementSet::finish() {
  measurements_.clear();
  marks_.appendSorted(measurements_);
  return measurements_;
}

std::span<const Measurement> MeasurementSet::build(std::span<const Eigen::Vector3d> origins,
                                                   std::span<const Eigen::Vector3d> endpoints) {
  assert(origins.size() == endpoints.size());
  begin();
  for (std::size_t i = 0; i < origins.size(); ++i) addReturn(origins[i], endpoints[i]);
  return finish();
}

}  // namespace ogf::fusion
