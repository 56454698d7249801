// What separates the robot's odometry from the true trajectory: a drift model integrated along the
// motion (scale error, heading drift per metre and per second, random walks) plus white jitter on each
// reported sample. Named presets make a model one word on the command line; add one by adding a row to
// the table in odometry_error.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/sim/trajectory.hpp"

namespace ogf::sim {

struct OdometryErrorModel {
  double scale_error = 0.0;              // fraction of each step's translation (a wrong wheel radius)
  double yaw_drift_per_m = 0.0;          // rad of heading error per metre travelled
  double yaw_bias_per_s = 0.0;           // rad/s of heading error (a gyro bias), accrued while moving or not
  double translation_walk_per_sqrt_m = 0.0;  // σ (m) of the translation random walk per √m travelled
  double yaw_walk_per_sqrt_m = 0.0;      // σ (rad) of the heading random walk per √m travelled
  double position_jitter_m = 0.0;        // σ (m) of white noise on each reported x, y (not accumulated)

  bool exact() const {
    return scale_error == 0.0 && yaw_drift_per_m == 0.0 && yaw_bias_per_s == 0.0 &&
           translation_walk_per_sqrt_m == 0.0 && yaw_walk_per_sqrt_m == 0.0 && position_jitter_m == 0.0;
  }
};

// "none" (odometry = truth), "mild" (a good wheel-inertial odometry), "wheel" (plain wheel odometry), and
// the drift presets that need pose correction: "wheel-slip" (3 % scale, 0.01 rad/m heading drift, random
// walks 0.02 m and 0.005 rad per sqrt(m)), "gyro-bias" (0.0035 rad/s heading bias only) and "slip-and-bias"
// (both). Magnitudes and their reasons: the table in odometry_error.cpp.
std::vector<std::string> odometryErrorPresetNames();
Result<OdometryErrorModel> odometryErrorPreset(std::string_view name);

struct StampedPose {
  std::int64_t utime = 0;  // µs since the epoch
  Pose pose;
};

// The odometry a robot would report along `truth` (consecutive samples of the true body pose): the first
// sample equals the truth (the odometry frame starts on the world frame) and every later one composes the
// true relative motion corrupted by `model`. Deterministic for a seed.
std::vector<StampedPose> simulateOdometry(const std::vector<StampedPose>& truth, const OdometryErrorModel& model,
                                          std::uint64_t seed);

}  // namespace ogf::sim
