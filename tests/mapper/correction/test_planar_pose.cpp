// The 3-D <-> planar pose conversions of the correction stage.
#include <gtest/gtest.h>

#include <numbers>

#include "ogf/correction/planar_pose.hpp"

namespace oc = ogf::correction;

namespace {
Eigen::Isometry3d tiltedPose() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(-0.03, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  t.translation() = Eigen::Vector3d(3.0, -2.0, 0.4);
  return t;
}
}  // namespace

TEST(PlanarPose, ReadsXYAndHeadingOfATiltedBody) {
  const auto p = oc::planarPoseOf(tiltedPose());
  EXPECT_DOUBLE_EQ(p.x, 3.0);
  EXPECT_DOUBLE_EQ(p.y, -2.0);
  EXPECT_NEAR(p.theta, 0.7, 1e-12);
}

TEST(PlanarPose, CorrectingToItsOwnPlanarPoseIsTheIdentity) {
  const auto c = oc::correctionBetween(tiltedPose(), oc::planarPoseOf(tiltedPose()));
  EXPECT_TRUE(c.isApprox(Eigen::Isometry3d::Identity(), 1e-12));
}

TEST(PlanarPose, CorrectionMovesXYAndHeadingAndKeepsHeightRollAndPitch) {
  const Eigen::Isometry3d odom = tiltedPose();
  const ogf::slam::Pose2 corrected{2.5, -1.0, -2.9};
  const Eigen::Isometry3d map = oc::correctionBetween(odom, corrected) * odom;
  const auto p = oc::planarPoseOf(map);
  EXPECT_NEAR(p.x, corrected.x, 1e-12);
  EXPECT_NEAR(p.y, corrected.y, 1e-12);
  EXPECT_NEAR(p.theta, corrected.theta, 1e-12);
  EXPECT_NEAR(map.translation().z(), odom.translation().z(), 1e-12);
  // The body's up vector keeps its angle to the vertical (roll and pitch untouched).
  EXPECT_NEAR(map.linear().col(2).z(), odom.linear().col(2).z(), 1e-12);
}
