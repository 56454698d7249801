// Read-only questions to a banded map: everything about one cell (latent mean and variance, Φ(m), the
// predictive probability, the class of eq. (3), entropy) and a summary over an axis-aligned box of cells.
// Cells never allocated answer with the prior: mean 0, variance Σ0_ii, unknown.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstddef>
#include <cstdint>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/common/result.hpp"

namespace ogf::filter {

struct CellQuery {
  CellKey key;
  double mean = 0.0;
  double variance = 0.0;
  double occupancyProbability = 0.5;   // Φ(m), what eq. (3) thresholds
  double predictiveProbability = 0.5;  // Φ(m/√(1+s))
  std::int8_t occupancyClass = 0;      // +1 occupied, -1 free, 0 unknown
  double entropyBits = 1.0;            // binary entropy of the predictive probability
  bool allocated = false;
};

CellQuery queryCell(const BandedOgf& map, const CellKey& key);

struct BoxSummary {
  std::size_t cells = 0;
  std::size_t allocated = 0;
  std::size_t occupied = 0;
  std::size_t free = 0;
  std::size_t unknown = 0;
  double entropyBits = 0.0;   // summed over the box
  double meanVariance = 0.0;
};

// Cells with lo ≤ key ≤ hi on every axis (inclusive). Error when lo > hi on an axis or the box holds more
// than `maxCells` cells.
Result<BoxSummary> summariseBox(const BandedOgf& map, const CellKey& lo, const CellKey& hi,
                                std::size_t maxCells = 100'000'000);

}  // namespace ogf::filter
