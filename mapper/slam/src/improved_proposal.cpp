// The Gaussian fit of τ and the draw from it.
#include "ogf/slam/improved_proposal.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "config_errors.hpp"

namespace ogf::slam {

Status ProposalConfig::validate() const {
  if (samples_per_axis < 1 || samples_per_axis > 9)
    return fieldError("samples_per_axis", "must be in [1, 9]", samples_per_axis);
  if (!(sample_step_m > 0.0) || !std::isfinite(sample_step_m))
    return fieldError("sample_step_m", "must be > 0", sample_step_m);
  if (!(sample_step_rad > 0.0) || !std::isfinite(sample_step_rad)) {
    return fieldError("sample_step_rad", "must be > 0", sample_step_rad);
  }
  if (!(min_sigma_m >= 0.0)) return fieldError("min_sigma_m", "must be >= 0", min_sigma_m);
  if (!(min_sigma_rad >= 0.0)) return fieldError("min_sigma_rad", "must be >= 0", min_sigma_rad);
  return okStatus();
}

std::vector<Pose2> proposalSamplePoses(const Pose2& centre, const ProposalConfig& config) {
  const int n = config.samples_per_axis;
  const double half = 0.5 * (n - 1);
  std::vector<Pose2> out;
  out.reserve(static_cast<std::size_t>(n * n * n));
  // The centre first, so fitGaussianProposal's angle reference is x*.
  out.push_back(centre);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const double dx = (i - half) * config.sample_step_m, dy = (j - half) * config.sample_step_m;
        const double dt = (k - half) * config.sample_step_rad;
        if (dx == 0.0 && dy == 0.0 && dt == 0.0) continue;
        out.push_back({centre.x + dx, centre.y + dy, normalizeAngle(centre.theta + dt)});
      }
    }
  }
  return out;
}

GaussianProposal fitGaussianProposal(std::span<const Pose2> samples, std::span<const double> log_tau,
                                     const ProposalConfig& config) {
  GaussianProposal g;
  const double max_l = *std::max_element(log_tau.begin(), log_tau.end());
  double eta = 0.0;  // Σ τ_j / exp(max_l)
  Eigen::Vector3d mu = Eigen::Vector3d::Zero();
  const double theta0 = samples[0].theta;
  std::vector<Eigen::Vector3d> v(samples.size());
  std::vector<double> a(samples.size());
  for (std::size_t j = 0; j < samples.size(); ++j) {
    v[j] = {samples[j].x, samples[j].y, normalizeAngle(samples[j].theta - theta0)};
    a[j] = std::exp(log_tau[j] - max_l);
    eta += a[j];
    mu += a[j] * v[j];
  }
  mu /= eta;
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < samples.size(); ++j) {
    const Eigen::Vector3d d = v[j] - mu;
    sigma += a[j] * d * d.transpose();
  }
  sigma /= eta;
  sigma(0, 0) += config.min_sigma_m * config.min_sigma_m;
  sigma(1, 1) += config.min_sigma_m * config.min_sigma_m;
  sigma(2, 2) += config.min_sigma_rad * config.min_sigma_rad;
  g.mean = {mu.x(), mu.y(), normalizeAngle(theta0 + mu.z())};
  g.covariance = sigma;
  g.log_eta = max_l + std::log(eta);
  return g;
}

Pose2 drawFromProposal(const GaussianProposal& proposal, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const double n0 = n(rng), n1 = n(rng), n2 = n(rng);
  const Eigen::Matrix3d l = proposal.covariance.llt().matrixL();
  const Eigen::Vector3d d = l * Eigen::Vector3d(n0, n1, n2);
  return {proposal.mean.x + d.x(), proposal.mean.y + d.y(), normalizeAngle(proposal.mean.theta + d.z())};
}

}  // namespace ogf::slam
