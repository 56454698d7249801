// The odometry motion model p(x_t | x_{t-1}, u_t) of gmapping (MotionModel::drawFromMotion): the
// odometry step u = (dx, dy, dθ) in the previous pose's frame is disturbed by independent Gaussian noise
// whose standard deviations grow linearly with the step:
//   σx = srr·|dx| + sxy·|dy| + str·|dθ|,  σy = srr·|dy| + sxy·|dx| + str·|dθ|,  σθ = stt·|dθ| + srt·‖(dx,dy)‖
// (each floored at a small minimum so a standing robot still has a proper density).
#pragma once

#include <random>

#include "ogf/common/result.hpp"
#include "ogf/slam/pose2.hpp"

namespace ogf::slam {

struct MotionModelConfig {
  // gmapping's defaults (slam_gmapping srr, srt, str, stt; sxy = 0.3·srr as in gmapping's gsp).
  double srr = 0.1;   // translation noise per metre of translation, m/m
  double srt = 0.2;   // rotation noise per metre of translation, rad/m
  double str = 0.1;   // translation noise per radian of rotation, m/rad
  double stt = 0.2;   // rotation noise per radian of rotation, rad/rad
  double sxy = 0.03;  // sideways noise per metre of the other axis, m/m
  double min_sigma_m = 0.005;
  double min_sigma_rad = 0.0025;

  Status validate() const;
};

// p(x_t | x_{t-1}, u_t) for one particle and one odometry step: a Gaussian over the step, in the frame
// of the previous pose.
struct MotionGaussian {
  Pose2 previous;  // x_{t-1}
  Pose2 step;      // u_t, the odometry step in the frame of x_{t-1}
  double sigma_x = 0.0;
  double sigma_y = 0.0;
  double sigma_theta = 0.0;

  Pose2 mean() const { return compose(previous, step); }
  // log p(x | x_{t-1}, u_t) up to a constant: −½ Σ (e_i / σ_i)², e = (x_{t-1}⁻¹ ⊕ x) − u.
  double logDensity(const Pose2& x) const;
};

class MotionModel {
 public:
  explicit MotionModel(const MotionModelConfig& config) : config_(config) {}

  MotionGaussian predict(const Pose2& previous, const Pose2& odometry_step) const;
  // A draw from p(x_t | x_{t-1}, u_t).
  static Pose2 sample(const MotionGaussian& g, std::mt19937_64& rng);

 private:
  MotionModelConfig config_;
};

}  // namespace ogf::slam
