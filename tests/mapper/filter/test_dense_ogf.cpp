// The dense OGF computes eq. (5) as the paper writes it, and one update matches the exact moments of
// prior × probit likelihood (Sec. IV: the KL projection of eq. (4)).
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/inverse_mills.hpp"

namespace ogf::filter {
namespace {

Eigen::MatrixXd smallPrior() {
  Eigen::MatrixXd k(3, 3);
  k << 0.40, 0.20, 0.05, 0.20, 0.40, 0.20, 0.05, 0.20, 0.40;
  return k;
}

TEST(DenseOgf, UpdateEqualsEquationFiveAsWritten) {
  DenseOgf ogf(smallPrior());
  Eigen::VectorXd m = Eigen::VectorXd::Zero(3);
  Eigen::MatrixXd sigma = smallPrior();
  const int cells[] = {0, 2, 1, 0, 2};
  const int ys[] = {1, -1, 1, 1, 1};
  for (int k = 0; k < 5; ++k) {
    const int i = cells[k];
    const double y = ys[k];
    // Eq. (5) term by term: η = Φ(y·m_i/√(Σ_ii+1)), mean step, then Σ minus the outer product of the mean
    // step minus the second term.
    const double s = sigma(i, i);
    const double arg = y * m(i) / std::sqrt(s + 1.0);
    const double eta = normalCdf(arg);
    const Eigen::VectorXd col = sigma.col(i);
    const Eigen::VectorXd step = y * col * normalPdf(arg) / (eta * std::sqrt(s + 1.0));
    sigma = sigma - step * step.transpose() -
            y * col * col.transpose() * normalPdf(arg) * m(i) / (eta * std::pow(s + 1.0, 1.5));
    m += step;
    ogf.update(i, ys[k]);
  }
  EXPECT_LT((ogf.mean() - m).norm(), 1e-12);
  EXPECT_LT((ogf.covariance() - sigma).norm(), 1e-12);
}

TEST(DenseOgf, OneUpdateMatchesExactMomentsOfTheTiltedPrior) {
  // Prior N(0.3, 0.5) on one cell, likelihood Φ(-m): moments by quadrature.
  DenseOgf ogf(Eigen::MatrixXd::Constant(1, 1, 0.5));
  ogf.update(0, 1);   // moves the mean away from 0
  const double m0 = ogf.mean()(0);
  const double s0 = ogf.covariance()(0, 0);
  double z0 = 0.0;
  double z1 = 0.0;
  double z2 = 0.0;
  for (int k = -200000; k <= 200000; ++k) {
    const double x = m0 + static_cast<double>(k) * 1e-4 * std::sqrt(s0);
    const double w = std::exp(-(x - m0) * (x - m0) / (2 * s0)) * normalCdf(-x);
    z0 += w;
    z1 += w * x;
    z2 += w * x * x;
  }
  const double mean = z1 / z0;
  const double var = z2 / z0 - mean * mean;
  ogf.update(0, -1);
  EXPECT_NEAR(ogf.mean()(0), mean, 1e-7);
  EXPECT_NEAR(ogf.covariance()(0, 0), var, 1e-7);
}

}  // namespace
}  // namespace ogf::filter
