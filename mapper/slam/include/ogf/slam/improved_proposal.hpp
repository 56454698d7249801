// The improved proposal of Grisetti et al. 2007 (Sec. IV, eq. 9–16; the lecture's "Gaussian proposal"):
// around the scan matcher's maximum x*, K poses x_j are evaluated with τ(x_j) = p(z | x_j, m)·p(x_j |
// x_{t−1}, u); the proposal is N(μ, Σ) with
//   μ = (1/η) Σ_j x_j τ(x_j),   Σ = (1/η) Σ_j (x_j − μ)(x_j − μ)ᵀ τ(x_j),   η = Σ_j τ(x_j),
// and the particle's weight is multiplied by η (eq. 16), which approximates ∫ p(z | x, m) p(x | x_{t−1}, u)
// dx.
#pragma once

#include <Eigen/Core>
#include <random>
#include <span>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam/pose2.hpp"

namespace ogf::slam {

struct ProposalConfig {
  // The K = samples_per_axis³ poses x_j form a grid centred on x*, this far apart per axis. gmapping
  // samples ±0.01 m / ±0.005 rad (llsamplerange, lasamplerange); a wider grid keeps more of τ's mass.
  int samples_per_axis = 3;
  double sample_step_m = 0.02;
  double sample_step_rad = 0.01;
  // Added to Σ's diagonal (as variances σ²) so a τ concentrated on one sample still gives a proper
  // Gaussian.
  double min_sigma_m = 0.002;
  double min_sigma_rad = 0.001;

  Status validate() const;
};

struct GaussianProposal {
  Pose2 mean;                                            // μ
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // Σ over (x, y, θ)
  double log_eta = 0.0;                                  // log Σ_j τ(x_j)
};

// The sample grid x_j around `centre`.
std::vector<Pose2> proposalSamplePoses(const Pose2& centre, const ProposalConfig& config);

// μ, Σ and log η from the poses x_j and log τ(x_j). Angles are averaged as offsets from x_0's heading,
// so a grid across ±π does not average to 0. `samples` must not be empty.
GaussianProposal fitGaussianProposal(std::span<const Pose2> samples, std::span<const double> log_tau,
                                     const ProposalConfig& config);

// A draw from N(μ, Σ).
Pose2 drawFromProposal(const GaussianProposal& proposal, std::mt19937_64& rng);

}  // namespace ogf::slam
