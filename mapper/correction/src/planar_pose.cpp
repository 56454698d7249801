#include "ogf/correction/planar_pose.hpp"

#include <cmath>

namespace ogf::correction {

slam::Pose2 planarPoseOf(const Eigen::Isometry3d& odom_from_body) {
  const Eigen::Vector3d forward = odom_from_body.linear().col(0);
  const Eigen::Vector3d& t = odom_from_body.translation();
  return {t.x(), t.y(), slam::normalizeAngle(std::atan2(forward.y(), forward.x()))};
}

Eigen::Isometry3d liftPlanarPose(const slam::Pose2& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(pose.theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(pose.x, pose.y, 0.0);
  return t;
}

Eigen::Isometry3d correctionBetween(const Eigen::Isometry3d& odom_from_body, const slam::Pose2& corrected) {
  // Both planar poses lifted to 3-D differ only in x, y and yaw, so the correction is a rotation about z
  // plus a horizontal translation and leaves height, roll and pitch alone.
  return liftPlanarPose(corrected) * liftPlanarPose(planarPoseOf(odom_from_body)).inverse();
}

}  // namespace ogf::correction
