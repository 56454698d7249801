// The improved proposal's Gaussian fit (μ, Σ, η of Grisetti et al. 2007, eq. 12–14) on known τ.
#include <gtest/gtest.h>

#include <cmath>
#include <ogf/slam/improved_proposal.hpp>
#include <random>
#include <vector>

namespace ogf::slam {
namespace {

ProposalConfig noFloor() {
  ProposalConfig c;
  c.min_sigma_m = 0.0;
  c.min_sigma_rad = 0.0;
  return c;
}

TEST(ImprovedProposal, FitMatchesAHandComputedTwoPointCase) {
  // τ = 1 at x = 0 and τ = 3 at x = 1: μ = 0.75, Σxx = (1·0.75² + 3·0.25²) / 4 = 0.1875, η = 4.
  const std::vector<Pose2> xs{{0, 0, 0}, {1, 0, 0}};
  const std::vector<double> log_tau{std::log(1.0), std::log(3.0)};
  const GaussianProposal g = fitGaussianProposal(xs, log_tau, noFloor());
  EXPECT_NEAR(g.mean.x, 0.75, 1e-12);
  EXPECT_NEAR(g.mean.y, 0.0, 1e-12);
  EXPECT_NEAR(g.covariance(0, 0), 0.1875, 1e-12);
  EXPECT_NEAR(g.covariance(1, 1), 0.0, 1e-12);
  EXPECT_NEAR(g.log_eta, std::log(4.0), 1e-12);
}

TEST(ImprovedProposal, LogEtaIsExactForHugeLogLikelihoods) {
  const std::vector<Pose2> xs{{0, 0, 0}, {1, 0, 0}};
  const std::vector<double> log_tau{-2000.0, -2000.0};
  EXPECT_NEAR(fitGaussianProposal(xs, log_tau, noFloor()).log_eta, -2000.0 + std::log(2.0), 1e-9);
}

TEST(ImprovedProposal, GaussianTauGivesItsMeanAndOrdersTheVariances) {
  // τ a Gaussian centred off the grid's centre, wider in x than in y.
  ProposalConfig c = noFloor();
  c.samples_per_axis = 9;
  c.sample_step_m = 0.01;
  c.sample_step_rad = 0.005;
  const Pose2 centre{1.0, 2.0, 3.1};  // near +π: angles must not wrap into the average
  const Pose2 m{1.005, 1.997, normalizeAngle(3.1 + 0.004)};
  const double sx = 0.012, sy = 0.006, st = 0.006;
  const std::vector<Pose2> xs = proposalSamplePoses(centre, c);
  ASSERT_EQ(xs.size(), 729U);
  std::vector<double> log_tau;
  for (const Pose2& x : xs) {
    const double ex = (x.x - m.x) / sx, ey = (x.y - m.y) / sy, et = normalizeAngle(x.theta - m.theta) / st;
    log_tau.push_back(-0.5 * (ex * ex + ey * ey + et * et) - 500.0);
  }
  const GaussianProposal g = fitGaussianProposal(xs, log_tau, c);
  EXPECT_NEAR(g.mean.x, m.x, 0.001);
  EXPECT_NEAR(g.mean.y, m.y, 0.001);
  EXPECT_NEAR(normalizeAngle(g.mean.theta - m.theta), 0.0, 0.001);
  EXPECT_GT(g.covariance(0, 0), 2.0 * g.covariance(1, 1));
  EXPECT_NEAR(std::sqrt(g.covariance(1, 1)), sy, 0.001);
  EXPECT_NEAR(g.covariance(0, 1), 0.0, 1e-6);
}

TEST(ImprovedProposal, DrawsFollowTheFittedGaussian) {
  GaussianProposal g;
  g.mean = {1.0, -1.0, 0.5};
  g.covariance = Eigen::Vector3d(0.01 * 0.01, 0.02 * 0.02, 0.005 * 0.005).asDiagonal();
  std::mt19937_64 rng(7);
  double sx = 0, sy = 0, sxx = 0, syy = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const Pose2 p = drawFromProposal(g, rng);
    sx += p.x - 1.0;
    sy += p.y + 1.0;
    sxx += (p.x - 1.0) * (p.x - 1.0);
    syy += (p.y + 1.0) * (p.y + 1.0);
  }
  EXPECT_NEAR(sx / n, 0.0, 0.001);
  EXPECT_NEAR(sy / n, 0.0, 0.002);
  EXPECT_NEAR(std::sqrt(sxx / n), 0.01, 0.001);
  EXPECT_NEAR(std::sqrt(syy / n), 0.02, 0.002);
}

TEST(ImprovedProposal, SampleGridHasKPosesCentredFirst) {
  const std::vector<Pose2> xs = proposalSamplePoses({1, 2, 0.3}, ProposalConfig{});
  ASSERT_EQ(xs.size(), 27U);
  EXPECT_DOUBLE_EQ(xs[0].x, 1.0);
  EXPECT_DOUBLE_EQ(xs[0].theta, 0.3);
}

}  // namespace
}  // namespace ogf::slam
