// Absolute trajectory error (ATE) of an estimated trajectory (raw odometry, or poses corrected by SLAM)
// against the simulator's true trajectory: per estimated pose, the Euclidean distance between its position
// and the true position at the same stamp; RMSE, mean and maximum over the poses (Sturm et al. 2012's ATE).
// No alignment transform is fitted: ogf-sim starts the odometry frame on the world frame (odometry.csv's
// first pose is the true one), so the frames already coincide and any offset is error.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ogf/sim/odometry_error.hpp"

namespace ogf::eval {

struct TrajectoryError {
  double rmse_m = 0.0;
  double mean_m = 0.0;
  double max_m = 0.0;
  std::size_t matched = 0;    // estimated poses scored
  std::size_t unmatched = 0;  // estimated poses outside the truth's time span or in a gap of it
};

// Matches each estimated stamp to the truth: the true sample with the same utime, else the position
// interpolated linearly between the two true samples around it when they are at most `max_truth_gap_us`
// apart. `truth` must be sorted by utime.
TrajectoryError absoluteTrajectoryError(const std::vector<sim::StampedPose>& truth,
                                        const std::vector<sim::StampedPose>& estimate,
                                        std::int64_t max_truth_gap_us = 100'000);

}  // namespace ogf::eval
