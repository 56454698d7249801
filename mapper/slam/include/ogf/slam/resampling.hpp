// Selective resampling of the particle set (Grisetti et al. 2007, Sec. V; Doucet 1998): the normalised
// weights, the effective sample size n_eff = 1 / Σ w̃_i² that decides whether to resample, and
// low-variance (systematic) resampling (Thrun, Burgard, Fox, Probabilistic Robotics, Table 4.4).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace ogf::slam {

// w̃_i ∝ exp(gain · (l_i − max_j l_j)) for log weights l_i, summing to 1. gain = 1 gives the exact
// weights; gmapping tempers them with gain = 1 / (obsSigmaGain · N).
std::vector<double> normalizedWeights(std::span<const double> log_weights, double gain = 1.0);

// n_eff = 1 / Σ w̃_i² of normalised weights: N for equal weights, 1 when one particle holds all.
double effectiveSampleSize(std::span<const double> normalized_weights);

// The indices of the particles drawn by low-variance resampling: one random offset u ∈ [0, 1/N) and the
// N pointers u + k/N walked along the cumulative weights. `u01` is a uniform draw in [0, 1); the result
// is sorted, and particle i is drawn ⌊N·w̃_i⌋ or ⌈N·w̃_i⌉ times.
std::vector<std::size_t> lowVarianceResample(std::span<const double> normalized_weights, double u01);

}  // namespace ogf::slam
