// Mapping with known poses for one particle (Grisetti et al. 2007, Sec. IV, "the map is updated by
// computing p(m | x_{1:t}, z_{1:t})"): every beam of a scan visits the cells it crosses and hits the cell
// it ends in, as gmapping's ScanMatcher::registerScan does with its point accumulators.
#pragma once

#include "ogf/common/result.hpp"
#include "ogf/slam/planar_scan.hpp"
#include "ogf/slam/pose2.hpp"
#include "ogf/slam/tiled_grid.hpp"

namespace ogf::slam {

struct MapUpdateConfig {
  // Beams longer than this are cut here and mark free space only (gmapping's maxUrange). Long beams in
  // a corridor carry little and cost time; angular error grows with range.
  double usable_range_m = 25.0;
  double min_range_m = 0.05;  // shorter readings are ignored (the robot itself)
  // "No return" readings (at the sensor's maximum: 81.83, 81.91, 50.0 in the benchmark logs) mark free
  // space up to this range; 0 skips them, as gmapping does. A missing return can be glass or black
  // surfaces, so the default skips.
  double no_return_free_range_m = 0.0;

  Status validate() const;
};

// Integrates one scan taken at `robot_pose` (map frame) into `grid`.
void registerScan(TiledGrid& grid, const Pose2& robot_pose, const PlanarScan& scan,
                  const MapUpdateConfig& config);

}  // namespace ogf::slam
