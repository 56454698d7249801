// FusionConfig: defaults are valid, each wrong field is named in the error, the extrinsic is built right.
#include <ogf/fusion/fusion_config.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace ogf::fusion {
namespace {

::testing::AssertionResult failsNaming(const Status& s, const std::string& field) {
  if (s) return ::testing::AssertionFailure() << "accepted";
  if (s.error().message.find(field) != 0) {
    return ::testing::AssertionFailure() << "message does not start with " << field << ": " << s.error().message;
  }
  return ::testing::AssertionSuccess();
}

TEST(FusionConfig, DefaultsAreValid) { EXPECT_TRUE(FusionConfig{}.validate().ok()); }

TEST(FusionConfig, EachWrongFieldIsNamedWithItsPath) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  FusionConfig c;
  c.measurement.resolution_m = 0.0;
  EXPECT_TRUE(failsNaming(c.validate(), "measurement.resolution_m"));
  c = {};
  c.measurement.resolution_m = nan;
  EXPECT_TRUE(failsNaming(c.validate(), "measurement.resolution_m"));
  c = {};
  c.measurement.min_range_m = -1.0;
  EXPECT_TRUE(failsNaming(c.validate(), "measurement.min_range_m"));
  c = {};
  c.measurement.max_range_m = 0.3;  // below min range
  EXPECT_TRUE(failsNaming(c.validate(), "measurement.max_range_m"));
  c = {};
  c.measurement.max_range_m = 1e7;  // too many cells for CellKey
  EXPECT_TRUE(failsNaming(c.validate(), "measurement.max_range_m"));
  c = {};
  c.extrinsic.translation_m.x() = nan;
  EXPECT_TRUE(failsNaming(c.validate(), "extrinsic.translation_m"));
  c = {};
  c.extrinsic.quaternion = Eigen::Quaterniond(2.0, 0.0, 0.0, 0.0);
  EXPECT_TRUE(failsNaming(c.validate(), "extrinsic.quaternion"));
  c = {};
  c.pose_buffer.capacity = 1;
  EXPECT_TRUE(failsNaming(c.validate(), "pose_buffer.capacity"));
  c = {};
  c.pose_buffer.quaternion_tolerance = -0.1;
  EXPECT_TRUE(failsNaming(c.validate(), "pose_buffer.quaternion_tolerance"));
  c = {};
  c.pose_buffer.jump_translation_m = 0.0;
  EXPECT_TRUE(failsNaming(c.validate(), "pose_buffer.jump_translation_m"));
  c = {};
  c.pose_buffer.jump_rotation_rad = nan;
  EXPECT_TRUE(failsNaming(c.validate(), "pose_buffer.jump_rotation_rad"));
  c = {};
  c.pending.max_pose_wait_s = -1.0;
  EXPECT_TRUE(failsNaming(c.validate(), "pending.max_pose_wait_s"));
  c = {};
  c.pending.max_pending_scans = 0;
  EXPECT_TRUE(failsNaming(c.validate(), "pending.max_pending_scans"));
  c = {};
  c.pending.max_pending_points = 0;
  EXPECT_TRUE(failsNaming(c.validate(), "pending.max_pending_points"));
}

TEST(FusionConfig, ExtrinsicFromRpyRotatesAboutFixedAxesZYX) {
  ExtrinsicConfig e;
  e.translation_m = {0.1, 0.0, 0.5};
  e.rpy_rad = {0.0, 0.0, std::numbers::pi / 2.0};  // yaw 90°: sensor x points along body y
  const Eigen::Isometry3d t = e.bodyFromSensor();
  EXPECT_TRUE((t * Eigen::Vector3d(1.0, 0.0, 0.0)).isApprox(Eigen::Vector3d(0.1, 1.0, 0.5), 1e-12));
  e.rpy_rad = {std::numbers::pi / 2.0, 0.0, std::numbers::pi / 2.0};  // roll first, then yaw
  // Rz(90)·Rx(90)·ŷ = Rz(90)·ẑ = ẑ
  EXPECT_TRUE((e.bodyFromSensor().linear() * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST(FusionConfig, ExtrinsicQuaternionReplacesRpy) {
  ExtrinsicConfig e;
  e.rpy_rad = {1.0, 2.0, 3.0};
  e.quaternion = Eigen::Quaterniond(std::cos(std::numbers::pi / 4.0), 0.0, 0.0, std::sin(std::numbers::pi / 4.0));
  EXPECT_TRUE(e.validate().ok());
  EXPECT_TRUE((e.bodyFromSensor().linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

}  // namespace
}  // namespace ogf::fusion
