// The body's true motion: a smooth path through waypoints driven at constant speed, heading along the
// path (or a fixed pose when there is one waypoint). Every lidar firing and odometry sample asks it for
// the pose at its exact time.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf::sim {

// A trajectory as a scene file or trajectory file states it.
struct TrajectorySpec {
  std::vector<Eigen::Vector3d> waypoints;  // body origin, metres, world frame (z = 0 drives on the ground)
  double speed = 1.0;                      // m/s along the path
  bool loop = false;                       // closed path, driven round and round
  double yaw = 0.0;                        // radians; the heading when there is a single waypoint
};

// Pose of the body in the world: position and rotation body → world.
struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();

  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = orientation.toRotationMatrix();
    t.translation() = position;
    return t;
  }
};

class Trajectory {
 public:
  // Fails (naming the problem) on no waypoints, a non-positive speed, or a path of zero length.
  static Result<Trajectory> build(const TrajectorySpec& spec);

  // The pose `t` seconds after the start. An open path ends at its last waypoint and stays there.
  Pose poseAt(double t) const;

  // Path length, metres (0 for a static pose).
  double length() const { return length_; }

 private:
  // The path resampled every kStep metres of arc length (so lookup is one division): position and the
  // unwrapped heading.
  std::vector<Eigen::Vector3d> positions_;
  std::vector<double> headings_;
  double length_ = 0.0;
  double speed_ = 0.0;
  bool loop_ = false;
};

}  // namespace ogf::sim
