#include "ogf/pipeline/published_cells.hpp"

#include <ogf/filter/occupancy.hpp>

namespace ogf::pipeline {
namespace {

delta::PublishedCell publishedOf(const filter::FilterConfig& cfg, const CellKey& key, double mean, double variance) {
  const double p = filter::predictiveProbability(mean, variance);
  return {key, static_cast<std::int16_t>(filter::quantiseProbability(p)),
          filter::occupancyClass(mean, cfg.occupiedThreshold, cfg.freeThreshold), static_cast<float>(variance)};
}

}  // namespace

std::vector<delta::PublishedCell> publishedCellsOf(const filter::BandedOgf& filter) {
  std::vector<delta::PublishedCell> out;
  out.reserve(filter.allocatedCells());
  const auto& cfg = filter.config();
  filter.forEachCell([&](const CellKey& key, float mean, float variance) { out.push_back(publishedOf(cfg, key, mean, variance)); });
  return out;
}

std::vector<delta::PublishedCell> publishedCellsInSlabs(const filter::BandedOgf& filter, std::span<const CellKey> slabs) {
  std::vector<delta::PublishedCell> out;
  const auto& cfg = filter.config();
  for (const CellKey& slab : slabs) {
    for (unsigned local = 0; local < delta::PublishedBlock::kCells; ++local) {
      const CellKey key = delta::PublishedBlock::cellKey(slab, local);
      const filter::CellEstimate e = filter.estimate(key);
      if (e.allocated) out.push_back(publishedOf(cfg, key, e.mean, e.variance));
    }
  }
  return out;
}

void refreshStaleSlabs(const filter::BandedOgf& filter, delta::DeltaStream& stream) {
  if (stream.stale().empty()) return;
  const auto slabs = stream.staleSlabsToRead();
  if (slabs.empty()) return;
  stream.refreshStale(publishedCellsInSlabs(filter, slabs));
}

}  // namespace ogf::pipeline
