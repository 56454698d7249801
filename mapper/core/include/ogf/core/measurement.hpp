// One binary observation of one cell, the unit the whole mapping pipeline passes around: ray casting makes
// them (Sun et al. Sec. VI-B: every cell a ray crosses is free, the end cell occupied), the filter consumes
// them (eq. 5, likelihood Phi(y * m_i)), and the journal stores them.
#pragma once

#include <cstdint>

#include "ogf/core/cell_key.hpp"

namespace ogf {

struct Measurement {
  static constexpr std::int8_t kFree = -1;
  static constexpr std::int8_t kOccupied = 1;

  CellKey key;
  std::int8_t y = kFree;  // kOccupied or kFree

  friend constexpr bool operator==(const Measurement&, const Measurement&) = default;
};

}  // namespace ogf
