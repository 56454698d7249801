#include "ogf/pipeline/published_cells.hpp"

#include <ogf/filter/occupancy.hpp>

namespace ogf::pipeline {

std::vector<delta::PublishedCell> publishedCellsOf(const filter::BandedOgf& filter) {
  std::vector<delta::PublishedCell> out;
  out.reserve(filter.allocatedCells());
  const auto& cfg = filter.config();
  filter.forEachCell([&](const CellKey& key, float mean, float variance) {
    const double p = filter::predictiveProbability(mean, variance);
    out.push_back({key, static_cast<std::int16_t>(filter::quantiseProbability(p)),
                   filter::occupancyClass(mean, cfg.occupiedThreshold, cfg.freeThreshold), variance});
  });
  return out;
}

}  // namespace ogf::pipeline
