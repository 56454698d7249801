// One occupancy measurement of a cell (Sec. II): y = +1 occupied, y = -1 free.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstdint>

namespace ogf::filter {

struct Measurement {
  CellKey key;
  std::int8_t y = 1;
};

}  // namespace ogf::filter
