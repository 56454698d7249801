// Odometry error presets and the drift integration.
#include "ogf/sim/odometry_error.hpp"

#include <array>
#include <cmath>
#include <utility>

#include "ogf/sim/random.hpp"

namespace ogf::sim {
namespace {

// The preset table: name and model. Figures are typical of the kind of odometry named, not of a product.
// The drift presets (issue 8) are strong enough that mapping with raw odometry doubles walls:
// - wheel-slip: wheels that slip, one more than the other: 3 % scale error, 0.01 rad (0.57 deg) of heading
//   per metre, random walks of 0.02 m and 0.005 rad per sqrt(m);
// - gyro-bias: an uncalibrated MEMS gyro: 0.0035 rad/s (0.2 deg/s, 12 deg/min) of heading error, nothing else;
// - slip-and-bias: both at once.
constexpr OdometryErrorModel kWheelSlip{0.03, 0.01, 0.0, 0.02, 0.005, 0.0};
constexpr OdometryErrorModel kGyroBias{0.0, 0.0, 0.0035, 0.0, 0.0, 0.0};
constexpr OdometryErrorModel kSlipAndBias{0.03, 0.01, 0.0035, 0.02, 0.005, 0.0};

const std::array<std::pair<std::string_view, OdometryErrorModel>, 6> kPresets = {{
    {"none", OdometryErrorModel{}},
    {"mild", OdometryErrorModel{0.002, 0.0005, 0.0, 0.002, 0.0005, 0.002}},
    {"wheel", OdometryErrorModel{0.01, 0.003, 0.0002, 0.01, 0.002, 0.005}},
    {"wheel-slip", kWheelSlip},
    {"gyro-bias", kGyroBias},
    {"slip-and-bias", kSlipAndBias},
}};

// Stream number of the odometry noise (the lidar uses 1 + packet index, which never reaches it).
constexpr std::uint64_t kOdometryStream = 0xFFFF'FFFF'FFFF'FFF0ULL;

}  // namespace

std::vector<std::string> odometryErrorPresetNames() {
  std::vector<std::string> names;
  for (const auto& [name, model] : kPresets) names.emplace_back(name);
  return names;
}

Result<OdometryErrorModel> odometryErrorPreset(std::string_view name) {
  for (const auto& [n, model] : kPresets) {
    if (n == name) return model;
  }
  std::string known;
  for (const auto& n : odometryErrorPresetNames()) known += (known.empty() ? "" : ", ") + n;
  return Error{"no odometry error preset named '" + std::string(name) + "' (presets: " + known + ")"};
}

std::vector<StampedPose> simulateOdometry(const std::vector<StampedPose>& truth, const OdometryErrorModel& model,
                                          std::uint64_t seed) {
  if (model.exact() || truth.empty()) return truth;
  Random rng(seed, kOdometryStream);
  std::vector<StampedPose> out;
  out.reserve(truth.size());
  Eigen::Isometry3d odom = truth.front().pose.isometry();
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (i > 0) {
      const Eigen::Isometry3d step = truth[i - 1].pose.isometry().inverse() * truth[i].pose.isometry();
      const double dist = step.translation().norm();
      const double dt = static_cast<double>(truth[i].utime - truth[i - 1].utime) * 1e-6;
      Eigen::Vector3d t = step.translation() * (1.0 + model.scale_error);
      const double walk = model.translation_walk_per_sqrt_m * std::sqrt(dist);
      t.x() += walk * rng.normal();
      t.y() += walk * rng.normal();
      const double dyaw = model.yaw_drift_per_m * dist + model.yaw_bias_per_s * dt +
                          model.yaw_walk_per_sqrt_m * std::sqrt(dist) * rng.normal();
      Eigen::Isometry3d noisy = Eigen::Isometry3d::Identity();
      noisy.linear() = Eigen::AngleAxisd(dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * step.linear();
      noisy.translation() = t;
      odom = odom * noisy;
    }
    StampedPose p{truth[i].utime, Pose{odom.translation(), Eigen::Quaterniond(odom.linear()).normalized()}};
    p.pose.position.x() += model.position_jitter_m * rng.normal();
    p.pose.position.y() += model.position_jitter_m * rng.normal();
    out.push_back(p);
  }
  return out;
}

}  // namespace ogf::sim
