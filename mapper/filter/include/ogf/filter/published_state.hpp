// What a map delta publishes of a cell, its class (eq. 3) and its quantised predictive probability
// round(10000·Φ(m/√(1+s))), computed fast enough to run on every cell an update touches: the class by
// comparing m with Φ⁻¹(r_o) and Φ⁻¹(r_f), computed once; the probability from a cubic Hermite table of Φ
// (nodes 1/64 apart on [−9, 9], derivative φ; absolute error about 1e-10). Near a threshold or a rounding
// boundary both fall back to the exact functions of occupancy.hpp, so the results always equal
// occupancyClass() and quantiseProbability(predictiveProbability()) (tested), at a few ns instead of an erfc.
#pragma once

#include <cstdint>
#include <span>

namespace ogf::filter {

// The published pair of one cell.
struct PublishedState {
  std::uint16_t quantisedProbability = 5000;
  std::int8_t occupancyClass = 0;
  bool operator==(const PublishedState&) const = default;
};

class PublishedStateRule {
 public:
  // Where the CPU has AVX2, statesOf works on eight cells at a time (the same states: the exact fallbacks
  // allow for its float m/√(1+s)).
  PublishedStateRule(double occupiedThreshold, double freeThreshold);
  // avx2 false: the scalar code only (for tests comparing the two).
  PublishedStateRule(double occupiedThreshold, double freeThreshold, bool avx2);

  std::int8_t occupancyClass(double mean) const;
  std::uint16_t quantisedProbability(double mean, double variance) const;
  PublishedState stateOf(double mean, double variance) const;
  // The states of many cells (out[i] of means[i], variances[i]; the spans of one size). With AVX2, eight
  // cells per step (m/√(1+s) in a vector of floats, the table's polynomial in two of doubles); otherwise in
  // stages over a few hundred cells at a time: all divisions and square roots, then all table look-ups, so
  // the long chain of dependent instructions of one cell overlaps with the others'. The rare exact fallbacks
  // last.
  void statesOf(std::span<const float> means, std::span<const float> variances, std::span<PublishedState> out) const;

 private:
  PublishedState exactStateOf(double mean, double variance) const;

  double occupiedThreshold_;
  double freeThreshold_;
  double occupiedZ_;  // Φ⁻¹(r_o)
  double freeZ_;      // Φ⁻¹(r_f)
  const double* value_;  // Φ at the table's nodes (one table per process)
  const double* slope_;  // φ at the nodes, times the node spacing
  bool avx2_ = false;
};

}  // namespace ogf::filter
