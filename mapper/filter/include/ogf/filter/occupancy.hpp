// What a cell's latent Gaussian N(m, s) says about occupancy: Φ(m) and the classes of eq. (3), the
// predictive probability Φ(m/√(1+s)) (the probability that a new measurement reads occupied), its
// quantisation for map deltas, and its entropy.
#pragma once

#include <cstdint>

namespace ogf::filter {

// Φ(m), the quantity eq. (3) thresholds.
double occupancyProbability(double mean);
// ∫ Φ(m) N(m; mean, variance) dm = Φ(mean/√(1+variance)).
double predictiveProbability(double mean, double variance);
// Eq. (3): +1 if Φ(m) > r_o, -1 if Φ(m) < r_f, else 0.
std::int8_t occupancyClass(double mean, double occupiedThreshold, double freeThreshold);
// round(p · 10000), p clamped to [0, 1].
std::uint16_t quantiseProbability(double p);
// Binary entropy of p, in bits (0 for p = 0 or 1, 1 for p = 0.5).
double binaryEntropyBits(double p);

}  // namespace ogf::filter
