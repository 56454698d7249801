// What a map delta publishes of a cell, its class (eq. 3) and its quantised predictive probability
// round(10000·Φ(m/√(1+s))), computed fast enough to run on every cell an update touches: the class by
// comparing m with Φ⁻¹(r_o) and Φ⁻¹(r_f), computed once; the probability from a cubic Hermite table of Φ
// (nodes 1/64 apart on [−9, 9], derivative φ; absolute error about 1e-10). Near a threshold or a rounding
// boundary both fall back to the exact functions of occupancy.hpp, so the results always equal
// occupancyClass() and quantiseProbability(predictiveProbability()) (tested), at a few ns instead of an erfc.
#pragma once

#include <cstdint>

namespace ogf::filter {

class PublishedStateRule {
 public:
  PublishedStateRule(double occupiedThreshold, double freeThreshold);

  std::int8_t occupancyClass(double mean) const;
  std::uint16_t quantisedProbability(double mean, double variance) const;

 private:
  double occupiedThreshold_;
  double freeThreshold_;
  double occupiedZ_;  // Φ⁻¹(r_o)
  double freeZ_;      // Φ⁻¹(r_f)
  const double* value_;  // Φ at the table's nodes (one table per process)
  const double* slope_;  // φ at the nodes, times the node spacing
};

}  // namespace ogf::filter
