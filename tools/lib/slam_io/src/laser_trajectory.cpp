// Collecting the laser records' robot poses of a CARMEN log into a stamped trajectory.
#include "ogf/slam_io/laser_trajectory.hpp"

#include <algorithm>

#include "ogf/slam_io/carmen_log.hpp"

namespace ogf::slam_io {

LaserTrajectory readLaserTrajectory(std::istream& in, const std::string& source_name) {
  LaserTrajectory trajectory;
  CarmenReader reader(in, source_name);
  while (auto record = reader.next()) {
    if (!record->ok()) {
      trajectory.malformed.push_back(record->error());
      continue;
    }
    if (const auto* laser = std::get_if<LaserRecord>(&record->value())) {
      trajectory.poses.push_back(StampedPose{laser->stamp.ipc_timestamp, laser->robot_pose});
    }
  }
  std::stable_sort(trajectory.poses.begin(), trajectory.poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
  trajectory.lines_read = reader.linesRead();
  return trajectory;
}

}  // namespace ogf::slam_io
