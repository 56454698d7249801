// The measurements of one scan (Sun et al. Sec. VI-B): each ray, from the sensor origin at the time of its
// point to its return, makes every cell it crosses free and its end cell occupied (Amanatides & Woo
// traversal, RayCaster). One measurement per cell per scan: occupied wins over free for the same cell, which
// is also what keeps a thin floor alive under the VLP-16's grazing rays. A return beyond max range is cut
// there and gives free cells only; a return closer than min range is ignored; a beam with no return gives
// free cells up to max range only when configured. The result comes in BrickOrder (cell_marks.hpp), so the
// same scan gives the same measurements in the same order whatever the order of its rays, and the filter
// finds the measurements of each of its blocks together.
//
//   MeasurementSet set(config.measurement);     // once; buffers are reused from scan to scan
//   set.begin();
//   for (each point) set.addReturn(origin_in_map, endpoint_in_map);
//   std::span<const Measurement> m = set.finish();   // valid until the next begin()
#pragma once

#include <ogf/core/measurement.hpp>
#include <ogf/fusion/cell_marks.hpp>
#include <ogf/fusion/fusion_config.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::fusion {

// What happened to the rays of the current scan.
struct RayCounts {
  std::int64_t returns = 0;             // rays that marked an occupied end cell
  std::int64_t cut_at_max_range = 0;    // returns beyond max range: free cells only
  std::int64_t ignored_min_range = 0;   // returns closer than min range
  std::int64_t no_return_free = 0;      // beams without a return that marked free space
  std::int64_t no_return_ignored = 0;   // beams without a return, free space disabled
  std::int64_t rejected_non_finite = 0; // NaN or infinite origin, endpoint or direction
  std::int64_t rejected_out_of_range = 0;  // a coordinate beyond 2^30 cells from 0, outside CellKey's reach
};

class MeasurementSet {
 public:
  // config must validate (MeasurementConfig::validate).
  explicit MeasurementSet(const MeasurementConfig& config);

  // Starts a new scan: forgets the previous one's marks, measurements and counts, keeps the buffers.
  void begin();

  // A beam that returned: origin (sensor position when the point was measured) and endpoint, map frame.
  void addReturn(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint);
  // A beam that did not return, along `direction` (any length > 0) from origin.
  void addNoReturn(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

  // The scan's measurements, in BrickOrder. Valid until the next begin().
  std::span<const Measurement> finish();

  // begin(), addReturn for each pair, finish(). origins.size() must equal endpoints.size().
  std::span<const Measurement> build(std::span<const Eigen::Vector3d> origins,
                                     std::span<const Eigen::Vector3d> endpoints);

  const RayCounts& counts() const { return counts_; }
  const MeasurementConfig& config() const { return config_; }

 private:
  void markFreeAlong(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint);
  // Finite and within CellKey's int32 range with margin; counts the ray when not.
  bool acceptable(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

  MeasurementConfig config_;
  double coordinate_limit_m_;  // 2^30 cells
  CellMarks marks_;
  MeasurementBuffer measurements_;
  RayCounts counts_;
};

}  // namespace ogf::fusion
