#include "ogf/map_io/map_cells.hpp"

#include <ogf/filter/occupancy.hpp>

#include <algorithm>

namespace ogf::map_io {

std::size_t MapCells::occupiedCount() const {
  return static_cast<std::size_t>(
      std::count_if(cells.begin(), cells.end(), [](const CellRecord& c) { return c.cell_class > 0; }));
}

MapCells collectCells(const filter::BandedOgf& map) {
  MapCells out;
  const auto& cfg = map.config();
  out.resolution = cfg.resolution;
  out.cells.reserve(map.allocatedCells());
  map.forEachCell([&](const CellKey& key, float mean, float variance) {
    out.cells.push_back({key, filter::predictiveProbability(mean, variance),
                         filter::occupancyClass(mean, cfg.occupiedThreshold, cfg.freeThreshold), variance});
  });
  return out;
}

}  // namespace ogf::map_io
