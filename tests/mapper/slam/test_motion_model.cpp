// The odometry motion model: its noise grows with the step, its draws follow it, its density peaks at
// the odometry prediction.
#include <gtest/gtest.h>

#include <cmath>
#include <ogf/slam/motion_model.hpp>
#include <random>

namespace ogf::slam {
namespace {

TEST(MotionModel, NoiseFollowsGmappingsLinearModel) {
  const MotionModel model(MotionModelConfig{});
  const MotionGaussian g = model.predict({0, 0, 0}, {1.0, 0.0, 0.5});
  EXPECT_NEAR(g.sigma_x, 0.1 * 1.0 + 0.1 * 0.5, 1e-12);      // srr·|dx| + str·|dθ|
  EXPECT_NEAR(g.sigma_y, 0.03 * 1.0 + 0.1 * 0.5, 1e-12);     // sxy·|dx| + str·|dθ|
  EXPECT_NEAR(g.sigma_theta, 0.2 * 0.5 + 0.2 * 1.0, 1e-12);  // stt·|dθ| + srt·‖d‖
  const MotionGaussian still = model.predict({0, 0, 0}, {0, 0, 0});
  EXPECT_GT(still.sigma_x, 0.0);
  EXPECT_GT(still.sigma_theta, 0.0);
}

TEST(MotionModel, DensityPeaksAtThePrediction) {
  const MotionModel model(MotionModelConfig{});
  const MotionGaussian g = model.predict({1, 1, 1.0}, {0.5, 0.0, 0.1});
  const Pose2 mean = g.mean();
  EXPECT_NEAR(g.logDensity(mean), 0.0, 1e-12);
  EXPECT_LT(g.logDensity({mean.x + 0.05, mean.y, mean.theta}), 0.0);
  EXPECT_LT(g.logDensity({mean.x, mean.y, mean.theta + 0.05}), 0.0);
}

TEST(MotionModel, DrawsScatterAroundThePredictionWithItsSpread) {
  const MotionModel model(MotionModelConfig{});
  const MotionGaussian g = model.predict({0, 0, 0}, {1.0, 0.0, 0.0});
  std::mt19937_64 rng(3);
  double sum = 0, sum_sq = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const double dx = MotionModel::sample(g, rng).x - 1.0;
    sum += dx;
    sum_sq += dx * dx;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.006);
  EXPECT_NEAR(std::sqrt(sum_sq / n), g.sigma_x, 0.006);
}

}  // namespace
}  // namespace ogf::slam
