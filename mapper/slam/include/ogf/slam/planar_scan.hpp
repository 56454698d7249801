// One planar range scan as the 2-D SLAM layer consumes it: ranges at evenly spaced bearings in the
// sensor frame, and where the sensor sits on the robot. A CARMEN FLASER record and a 3-D lidar scan cut to
// a height band (planar_projection.hpp) both become this.
#pragma once

#include <vector>

#include "ogf/slam/pose2.hpp"

namespace ogf::slam {

struct PlanarScan {
  double angle_min_rad = 0.0;        // bearing of ranges[0] in the sensor frame
  double angle_increment_rad = 0.0;  // bearing step between consecutive ranges
  double max_range_m = 0.0;          // a reading at or beyond it means "no return"
  std::vector<float> ranges_m;       // 0 or non-finite: no reading
  Pose2 sensor_pose;                 // the sensor in the robot (body) frame

  double bearing(std::size_t i) const { return angle_min_rad + static_cast<double>(i) * angle_increment_rad; }
  bool isNoReturn(float r) const { return static_cast<double>(r) >= max_range_m; }
  bool isValid(float r) const { return std::isfinite(r) && r > 0.0F; }
};

}  // namespace ogf::slam
