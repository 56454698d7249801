// One cell as the delta stream publishes it: the quantised predictive probability and class that a
// client sees, plus the variance at the time it was last published (map_delta_t's per-cell fields).
#pragma once

#include <ogf/map_delta_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ogf/core/cell_key.hpp"

namespace ogf::delta {

inline constexpr std::int16_t kProbabilityScale = ogf::map_delta_t::PROBABILITY_SCALE;
// A cell nobody published yet reads as the prior: probability 0.5, class unknown.
inline constexpr std::int16_t kPriorProbability = kProbabilityScale / 2;

struct PublishedCell {
  CellKey key;
  std::int16_t probability = kPriorProbability;  // p * kProbabilityScale, rounded
  std::int8_t cell_class = ogf::map_delta_t::CLASS_UNKNOWN;
  float variance = 0.0f;

  // Whether a client would see a difference: the quantised probability or the class changed. Variance
  // alone does not make a delta (it changes with every nearby measurement).
  bool visiblyDiffers(const PublishedCell& o) const {
    return probability != o.probability || cell_class != o.cell_class;
  }
};

// p in [0, 1] to the published integer, rounded to nearest; NaN reads as the prior.
inline std::int16_t quantiseProbability(double p) {
  if (!(p == p)) return kPriorProbability;
  const double scaled = std::round(std::clamp(p, 0.0, 1.0) * kProbabilityScale);
  return static_cast<std::int16_t>(scaled);
}

}  // namespace ogf::delta
