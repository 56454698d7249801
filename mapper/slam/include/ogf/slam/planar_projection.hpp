// A planar scan from a 3-D lidar scan: the points inside a height band of the body frame, projected onto
// the ground plane and binned by bearing, the nearest point per bin giving that bin's range. So a VLP-16
// robot feeds the same 2-D scan matcher and RBPF as a planar laser.
#pragma once

#include <Eigen/Core>
#include <span>

#include "ogf/common/result.hpp"
#include "ogf/slam/planar_scan.hpp"

namespace ogf::slam {

struct PlanarProjectionConfig {
  double z_min_m = 0.1;       // band bottom in the body frame: above the floor and its noise
  double z_max_m = 1.5;       // band top: below ceilings and overhangs a 2-D map should not hold
  double min_range_m = 0.4;   // nearer points (the robot, its mount) are dropped
  double max_range_m = 30.0;  // farther points are dropped; an empty bin reads max_range_m ("no return")
  int beams = 720;            // bins over 360°, the first centred on bearing −π (0.5° for 720)

  Status validate() const;
};

// `points_body` in the body frame (x forward, z up). The scan's sensor pose is the body origin.
PlanarScan projectToPlanarScan(std::span<const Eigen::Vector3f> points_body,
                               const PlanarProjectionConfig& config);

}  // namespace ogf::slam
