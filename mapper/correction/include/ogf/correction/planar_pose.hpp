// A robot pose in 3-D seen by a planar SLAM: its x, y and heading (the yaw about the odometry frame's z),
// and the way back: the 3-D transform that moves a planar pose to another while keeping height, roll and
// pitch as odometry measured them.
#pragma once

#include <Eigen/Geometry>

#include "ogf/slam/pose2.hpp"

namespace ogf::correction {

// x, y and the heading of the body's x axis projected on the ground plane.
slam::Pose2 planarPoseOf(const Eigen::Isometry3d& odom_from_body);

// The planar pose as a 3-D transform: a rotation by theta about z, then a translation by (x, y, 0).
Eigen::Isometry3d liftPlanarPose(const slam::Pose2& pose);

// The transform `map_from_odom` such that map_from_odom * odom_from_body has the planar pose `corrected`
// and the height, roll and pitch of odom_from_body.
Eigen::Isometry3d correctionBetween(const Eigen::Isometry3d& odom_from_body, const slam::Pose2& corrected);

}  // namespace ogf::correction
