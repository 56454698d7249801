// The pose files ogf-sim writes: the pose CSV of ogf/tools/pose_csv.hpp (one pose per line, µs since the
// epoch on the capture's clock, the body pose in the odometry or world frame) and an LCM log of
// ogf.odometry_t on channel POSE, as a robot's odometry would be recorded by lcm-logger.
#pragma once

#include <string>
#include <vector>

#include "ogf/sim/odometry_error.hpp"
#include "ogf/common/result.hpp"

namespace ogf::sim {

inline constexpr const char* kPoseChannel = "POSE";

Status writePoseCsv(const std::string& path, const std::vector<StampedPose>& poses);
// The poses of a pose CSV (ogf/tools/pose_csv.hpp); refuses a file with a malformed line, naming it.
Result<std::vector<StampedPose>> readPoseCsv(const std::string& path);

// One ogf.odometry_t per pose (frame "odom", child "base_link", no covariance), event time = utime.
Status writeOdometryLcmLog(const std::string& path, const std::vector<StampedPose>& poses);

}  // namespace ogf::sim
