// The fusion layer's configuration: typed structs with units in the field names, defaults for a VLP-16 on
// a ground robot, and validation that names the field that is wrong, so a bad configuration fails at
// start-up with a message instead of mapping garbage. The daemon fills FusionConfig from its file and
// hands each part to the component that uses it.
#pragma once

#include <ogf/common/result.hpp>

#include <Eigen/Geometry>

#include <ogf/fusion/time_sanity.hpp>

#include <cstddef>
#include <optional>

namespace ogf::fusion {

// How a scan becomes measurements (Sun et al. Sec. VI-B).
struct MeasurementConfig {
  double resolution_m = 0.2;  // cell edge, metres
  double min_range_m = 0.4;   // returns closer than this are ignored (the mount, the robot, near-field noise)
  double max_range_m = 30.0;  // returns beyond are cut here and give free cells only
  // A beam with no return marks free space up to max_range_m. Off by default: a missing return can be a
  // black or specular surface, not empty space.
  bool free_space_for_no_return = false;

  Status validate() const;
};

// Where the sensor sits on the body: the transform taking sensor-frame points to the body frame.
struct ExtrinsicConfig {
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();
  // Roll, pitch, yaw in radians, R = Rz(yaw)·Ry(pitch)·Rx(roll) (REP-103 / URDF fixed axes), used
  // when quaternion is empty.
  Eigen::Vector3d rpy_rad = Eigen::Vector3d::Zero();
  // Unit quaternion (w, x, y, z); when set, it replaces rpy_rad.
  std::optional<Eigen::Quaterniond> quaternion;

  Status validate() const;
  Eigen::Isometry3d bodyFromSensor() const;
};

// Validation and capacity of the odometry buffer.
struct PoseBufferConfig {
  std::size_t capacity = 4000;  // poses kept: 40 s of 100 Hz odometry
  // Largest |‖q‖ − 1| accepted (the quaternion is then normalised); beyond it the pose is rejected.
  double quaternion_tolerance = 1e-3;
  // max_pose_jump: a step between consecutive poses larger than either splits the trajectory there (the
  // pose is kept; scans spanning the step are dropped, never interpolated across it).
  double jump_translation_m = 1.0;
  double jump_rotation_rad = 0.5;
  // A coordinate farther from the odometry origin than this is absurd and the pose is refused. 10^7 m holds
  // UTM and Earth-centred coordinates; with 2^20 cells of range on top it keeps every cell key within
  // int32 down to 0.005 m cells.
  double max_abs_position_m = 1e7;

  Status validate() const;
};

// Scans waiting for the poses that cover them.
struct PendingScansConfig {
  double max_pose_wait_s = 0.5;        // a scan waits this long for its poses, then is dropped
  std::size_t max_pending_scans = 10;  // beyond either bound the oldest whole scan is dropped
  std::size_t max_pending_points = 400000;

  Status validate() const;
};

struct FusionConfig {
  MeasurementConfig measurement;
  ExtrinsicConfig extrinsic;
  PoseBufferConfig pose_buffer;
  PendingScansConfig pending;
  TimeSanityConfig time_sanity;  // the same bounds for the odometry and the scans

  // The first wrong field, named with its path ("measurement.max_range_m: ...").
  Status validate() const;
};

}  // namespace ogf::fusion
