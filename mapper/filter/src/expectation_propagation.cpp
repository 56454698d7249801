// EP for probit GP classification on grid cells, following the structure of GPML Alg. 3.5: sequential
// site updates with rank-1 covariance updates inside a sweep, and a fresh, numerically stable recomputation
// of the posterior from the site precisions after each sweep.
#include "ogf/filter/expectation_propagation.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "ogf/filter/probit_update.hpp"

namespace ogf::filter {
namespace {

// Posterior from the prior and per-cell site precision τ̃ and precision-mean ν̃:
// Σ = (K⁻¹ + diag τ̃)⁻¹ = K − K S½ B⁻¹ S½ K with B = I + S½ K S½ (GPML eq. 3.53 and Alg. 3.5, line 13),
// μ = Σ ν̃.
bool recompute(const Eigen::MatrixXd& prior, const Eigen::VectorXd& tau, const Eigen::VectorXd& nu,
               Eigen::MatrixXd& sigma, Eigen::VectorXd& mu) {
  const Eigen::VectorXd sqrtTau = tau.cwiseMax(0.0).cwiseSqrt();
  Eigen::MatrixXd b = sqrtTau.asDiagonal() * prior * sqrtTau.asDiagonal();
  b.diagonal().array() += 1.0;
  const Eigen::LLT<Eigen::MatrixXd> llt(b);
  if (llt.info() != Eigen::Success) {
    return false;
  }
  const Eigen::MatrixXd v = llt.matrixL().solve(sqrtTau.asDiagonal() * prior);
  sigma = prior - v.transpose() * v;
  mu = sigma * nu;
  return true;
}

}  // namespace

ExpectationPropagation::ExpectationPropagation(Eigen::MatrixXd prior, EpOptions options)
    : prior_(std::move(prior)), options_(options) {}

Result<EpPosterior> ExpectationPropagation::run(std::span<const EpSite> sites) const {
  const Eigen::Index n = prior_.rows();
  for (std::size_t s = 0; s < sites.size(); ++s) {
    if (sites[s].cell < 0 || sites[s].cell >= n || (sites[s].y != 1 && sites[s].y != -1)) {
      return Error{"expectation propagation: site " + std::to_string(s) + " has cell " +
                   std::to_string(sites[s].cell) + " and y " + std::to_string(sites[s].y) +
                   " (cells 0.." + std::to_string(n - 1) + ", y ±1)"};
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> priorCheck(prior_);
  if (priorCheck.info() != Eigen::Success) {
    return Error{"expectation propagation: the prior covariance is not positive definite"};
  }

  // Site natural parameters (precision τ̃_s, precision-mean ν̃_s); Algorithm 1 starts from σ̃ = ∞.
  std::vector<double> siteTau(sites.size(), 0.0);
  std::vector<double> siteNu(sites.size(), 0.0);
  Eigen::VectorXd cellTau = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd cellNu = Eigen::VectorXd::Zero(n);

  EpPosterior post;
  post.covariance = prior_;
  post.mean = Eigen::VectorXd::Zero(n);

  for (int sweep = 1; sweep <= options_.maxSweeps; ++sweep) {
    double largestChange = 0.0;
    for (std::size_t s = 0; s < sites.size(); ++s) {
      const Eigen::Index i = sites[s].cell;
      const double var = post.covariance(i, i);
      // Cavity q_{-s}(m_i), Algorithm 1 line 4.
      const double cavityTau = 1.0 / var - siteTau[s];
      const double cavityNu = post.mean(i) / var - siteNu[s];
      if (!(cavityTau > 0.0)) {
        continue;  // numerically degenerate cavity: leave this site as it is for this sweep
      }
      const double cavityVar = 1.0 / cavityTau;
      const double cavityMean = cavityNu * cavityVar;
      // Moments of cavity × Φ(y m), eq. (7).
      const ProbitUpdate u = probitUpdate(sites[s].y, cavityMean, cavityVar);
      const double hatMean = cavityMean + cavityVar * u.meanGain;
      const double hatVar = cavityVar - cavityVar * cavityVar * u.covShrink;
      // New site, eq. (8), in natural parameters.
      const double newTau = std::max(1.0 / hatVar - cavityTau, 0.0);
      const double newNu = hatMean / hatVar - cavityNu;
      const double deltaTau = newTau - siteTau[s];
      const double deltaNu = newNu - siteNu[s];
      largestChange = std::max({largestChange, std::abs(deltaTau), std::abs(deltaNu)});
      siteTau[s] = newTau;
      siteNu[s] = newNu;
      cellTau(i) += deltaTau;
      cellNu(i) += deltaNu;
      // Rank-1 update of Σ for the change of precision at cell i, then μ = Σ ν̃ (GPML Alg. 3.5 l. 10-11),
      // the latter in O(N): with Σ' = Σ − a c cᵀ and ν̃' = ν̃ + Δν e_i, Σ'ν̃' = μ − a c (cᵀ ν̃) + Δν Σ'[:, i].
      const Eigen::VectorXd column = post.covariance.col(i);
      const double a = deltaTau / (1.0 + deltaTau * var);
      const double projection = post.mean(i);  // cᵀ ν̃ = (Σ ν̃)_i before this site's change
      post.covariance.noalias() -= a * (column * column.transpose());
      post.mean -= (a * projection) * column;
      post.mean += deltaNu * post.covariance.col(i);
    }
    post.sweeps = sweep;
    if (largestChange < options_.tolerance) {
      post.converged = true;
      break;
    }
  }
  // The rank-1 updates drift slowly; the posterior is rebuilt from the sites once at the end (GPML rebuilds
  // after every sweep; at O(N³) per rebuild that dominated the cost for no visible change in double).
  if (!recompute(prior_, cellTau, cellNu, post.covariance, post.mean)) {
    return Error{"expectation propagation: posterior recomputation failed after " + std::to_string(post.sweeps) +
                 " sweeps"};
  }
  return post;
}

}  // namespace ogf::filter
