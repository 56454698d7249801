// Weight normalisation, n_eff and low-variance resampling.
#include "ogf/slam/resampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ogf::slam {

std::vector<double> normalizedWeights(std::span<const double> log_weights, double gain) {
  std::vector<double> w(log_weights.size(), 0.0);
  if (log_weights.empty()) return w;
  const double max_l = *std::max_element(log_weights.begin(), log_weights.end());
  double sum = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    w[i] = std::exp(gain * (log_weights[i] - max_l));
    sum += w[i];
  }
  for (double& v : w) v /= sum;
  return w;
}

double effectiveSampleSize(std::span<const double> normalized_weights) {
  double sum_sq = 0.0;
  for (double v : normalized_weights) sum_sq += v * v;
  return sum_sq > 0.0 ? 1.0 / sum_sq : 0.0;
}

std::vector<std::size_t> lowVarianceResample(std::span<const double> normalized_weights, double u01) {
  const std::size_t n = normalized_weights.size();
  std::vector<std::size_t> drawn;
  drawn.reserve(n);
  if (n == 0) return drawn;
  const double step = 1.0 / static_cast<double>(n);
  const double r = std::clamp(u01, 0.0, std::nextafter(1.0, 0.0)) * step;
  double cumulative = normalized_weights[0];
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double u = r + static_cast<double>(k) * step;
    while (u > cumulative && i + 1 < n) cumulative += normalized_weights[++i];
    drawn.push_back(i);
  }
  return drawn;
}

}  // namespace ogf::slam
