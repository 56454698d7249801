// What the banded filter reports after a batch of measurements: the cells whose class, eq. (3), or
// quantised predictive probability changed, for the mapper's map deltas.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstdint>
#include <span>

namespace ogf::filter {

struct CellChange {
  CellKey key;
  float mean = 0.0F;
  float variance = 0.0F;
  std::uint16_t quantisedProbability = 5000;  // round(p · 10000), p = Φ(m/√(1+s)) (predictive)
  std::int8_t occupancyClass = 0;             // eq. (3): +1 occupied, -1 free, 0 unknown
};

class ChangeSink {
 public:
  virtual ~ChangeSink() = default;
  // Called once per changed cell, in the map's deterministic cell order, after the batch, on the thread that
  // called update() (whatever the filter's threads).
  virtual void cellChanged(const CellChange& change) = 0;
  // The filter reports the changed cells a few hundred at a time through this, in the same order; by
  // default one cellChanged each. A sink that collects many cells overrides it: one virtual call a run.
  virtual void cellsChanged(std::span<const CellChange> changes) {
    for (const CellChange& c : changes) {
      cellChanged(c);
    }
  }
};

}  // namespace ogf::filter
