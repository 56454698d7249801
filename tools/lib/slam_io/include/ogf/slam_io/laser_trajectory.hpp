// The robot trajectory a CARMEN log's laser records carry (FLASER's second triple, ROBOTLASER1's
// robot_pose, each at its ipc_timestamp): what metricEvaluator reads from a SLAM result log, and the raw
// odometry when applied to an input log (docs/test-data.md §3.4).
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam_io/relations.hpp"

namespace ogf::slam_io {

struct LaserTrajectory {
  std::vector<StampedPose> poses;  // sorted by stamp
  std::vector<Error> malformed;    // one per malformed record line; the rest was still read
  std::size_t lines_read = 0;
};

LaserTrajectory readLaserTrajectory(std::istream& in, const std::string& source_name);

}  // namespace ogf::slam_io
