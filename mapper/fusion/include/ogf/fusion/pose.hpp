// A pose of the robot body in the odometry (map) frame at one instant: what odometry_t and bot_core.pose_t
// carry on POSE, reduced to what the fusion layer uses.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace ogf::fusion {

struct Pose {
  std::int64_t utime = 0;                                           // microseconds since the Unix epoch
  Eigen::Vector3d position = Eigen::Vector3d::Zero();               // body origin in the odometry frame, m
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // rotates body vectors into odometry

  // The transform taking body-frame points to the odometry frame.
  Eigen::Isometry3d odomFromBody() const {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = orientation.toRotationMatrix();
    t.translation() = position;
    return t;
  }
};

}  // namespace ogf::fusion
