// Every allocated cell of a banded OGF with what the exports write about it: the predictive probability
// Φ(m/√(1+s)) (what a client of the delta stream sees), the class of eq. (3) and the variance. One pass
// over the filter, in its deterministic order, shared by the CSV, PLY, OctoMap and PNG exports.
#pragma once

#include <ogf/core/cell_key.hpp>
#include <ogf/filter/banded_ogf.hpp>

#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace ogf::map_formats {

struct CellRecord {
  CellKey key;
  double probability = 0.5;  // predictive, in [0, 1]
  std::int8_t cell_class = 0;  // -1 free, 0 unknown, +1 occupied
  float variance = 0.0f;
};

struct MapCells {
  double resolution = 0.2;
  std::vector<CellRecord> cells;

  std::size_t occupiedCount() const;
};

MapCells collectCells(const filter::BandedOgf& map);

// The occupied cells as point records for the PLY and PCD exports: five little-endian floats each, the
// cell centre x, y, z in metres, p and variance.
std::vector<char> occupiedPointRecords(const MapCells& cells);
// Writes `header` then occupiedPointRecords to `path`; `kind` ("PLY") names the file in errors.
Status writeOccupiedPoints(const MapCells& cells, const std::filesystem::path& path, std::string_view header,
                           std::string_view kind);

}  // namespace ogf::map_formats
