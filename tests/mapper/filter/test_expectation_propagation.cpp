// EP (Algorithm 1) converges, equals one OGF update for a single site (Theorem 1), does not depend on the
// order of its sites once converged, and agrees with the exact posterior computed by brute force.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <vector>

#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/expectation_propagation.hpp"
#include "ogf/filter/inverse_mills.hpp"

namespace ogf::filter {
namespace {

// Gaussian kernel of σ = 1 grid unit, amplitude 1/(σ√2π), on an n × n grid (the paper's Sec. VI-A prior).
Eigen::MatrixXd gridPrior(int n) {
  Eigen::MatrixXd k(n * n, n * n);
  for (int a = 0; a < n * n; ++a) {
    for (int b = 0; b < n * n; ++b) {
      const double dx = a % n - b % n;
      const double dy = a / n - b / n;
      k(a, b) = std::exp(-(dx * dx + dy * dy) / 2.0) / std::sqrt(2.0 * 3.141592653589793);
    }
  }
  return k;
}

TEST(ExpectationPropagation, SingleSiteEqualsOneOgfUpdate) {
  const Eigen::MatrixXd prior = gridPrior(3);
  const std::vector<EpSite> sites = {{4, -1}};
  const auto ep = ExpectationPropagation(prior).run(sites);
  ASSERT_TRUE(ep.ok()) << ep.error().message;
  DenseOgf ogf(prior);
  ogf.update(4, -1);
  EXPECT_LT((ep->mean - ogf.mean()).norm(), 1e-10);
  EXPECT_LT((ep->covariance - ogf.covariance()).norm(), 1e-10);
}

TEST(ExpectationPropagation, ConvergesOnARandomSceneAndForgetsSiteOrder) {
  const int n = 8;
  const Eigen::MatrixXd prior = gridPrior(n);
  std::mt19937 rng(7);
  std::vector<EpSite> sites;
  for (int c = 0; c < n * n; ++c) {
    if (rng() % 3 != 0) {
      sites.push_back({c, (c % n) < n / 2 ? 1 : -1});
    }
  }
  const auto forward = ExpectationPropagation(prior).run(sites);
  ASSERT_TRUE(forward.ok());
  EXPECT_TRUE(forward->converged);
  EXPECT_LT(forward->sweeps, 50);
  std::vector<EpSite> reversed(sites.rbegin(), sites.rend());
  const auto backward = ExpectationPropagation(prior).run(reversed);
  ASSERT_TRUE(backward.ok());
  EXPECT_LT((forward->mean - backward->mean).norm() / forward->mean.norm(), 1e-6);
  // The OGF, a single forward pass, does depend on the order; EP is the order-free oracle.
  DenseOgf ogf(prior);
  for (const EpSite& s : sites) {
    ogf.update(s.cell, s.y);
  }
  EXPECT_LT((ogf.mean() - forward->mean).norm() / forward->mean.norm(), 0.04);  // eq. (12), Sec. VI-A
}

TEST(ExpectationPropagation, AgreesWithBruteForcePosteriorOnTwoCells) {
  Eigen::MatrixXd prior(2, 2);
  prior << 0.4, 0.25, 0.25, 0.4;
  const std::vector<EpSite> sites = {{0, 1}, {1, -1}, {0, 1}};
  const auto ep = ExpectationPropagation(prior, {1e-12, 200}).run(sites);
  ASSERT_TRUE(ep.ok());
  EXPECT_TRUE(ep->converged);

  // Exact posterior moments: N(m; 0, prior) Φ(m0)² Φ(-m1) integrated on a fine grid.
  const Eigen::MatrixXd inv = prior.inverse();
  double z = 0.0;
  Eigen::Vector2d first = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  const double h = 0.01;
  for (double a = -5.0; a <= 5.0; a += h) {
    for (double b = -5.0; b <= 5.0; b += h) {
      const Eigen::Vector2d m(a, b);
      const double w = std::exp(-0.5 * m.dot(inv * m)) * normalCdf(a) * normalCdf(a) * normalCdf(-b);
      z += w;
      first += w * m;
      second += w * m * m.transpose();
    }
  }
  const Eigen::Vector2d mean = first / z;
  const Eigen::Matrix2d cov = second / z - mean * mean.transpose();
  EXPECT_NEAR(ep->mean(0), mean(0), 0.02 * std::abs(mean(0)));
  EXPECT_NEAR(ep->mean(1), mean(1), 0.02 * std::abs(mean(1)));
  EXPECT_NEAR(ep->covariance(0, 0), cov(0, 0), 0.03 * cov(0, 0));
  EXPECT_NEAR(ep->covariance(1, 1), cov(1, 1), 0.03 * cov(1, 1));
  EXPECT_NEAR(ep->covariance(0, 1), cov(0, 1), 0.05 * std::abs(cov(0, 1)));
}

TEST(ExpectationPropagation, RejectsASiteOutsideTheGrid) {
  const std::vector<EpSite> sites = {{9, 1}};
  const auto ep = ExpectationPropagation(gridPrior(3)).run(sites);
  ASSERT_FALSE(ep.ok());
  EXPECT_NE(ep.error().message.find("site 0"), std::string::npos);
}

}  // namespace
}  // namespace ogf::filter
