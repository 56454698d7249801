// Occupancy probabilities, classes and entropy of one cell.
#include "ogf/filter/occupancy.hpp"

#include <algorithm>
#include <cmath>

#include "ogf/filter/inverse_mills.hpp"

namespace ogf::filter {

double occupancyProbability(double mean) { return normalCdf(mean); }

double predictiveProbability(double mean, double variance) {
  return normalCdf(mean / std::sqrt(1.0 + variance));
}

std::int8_t occupancyClass(double mean, double occupiedThreshold, double freeThreshold) {
  const double p = occupancyProbability(mean);
  if (p > occupiedThreshold) {
    return 1;
  }
  if (p < freeThreshold) {
    return -1;
  }
  return 0;
}

std::uint16_t quantiseProbability(double p) {
  return static_cast<std::uint16_t>(std::lround(std::clamp(p, 0.0, 1.0) * 10000.0));
}

double binaryEntropyBits(double p) {
  if (!(p > 0.0 && p < 1.0)) {
    return 0.0;
  }
  return -(p * std::log2(p) + (1.0 - p) * std::log2(1.0 - p));
}

}  // namespace ogf::filter
