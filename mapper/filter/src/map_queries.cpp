// Per-cell and per-box queries of the banded map.
#include "ogf/filter/map_queries.hpp"

#include <string>

#include "ogf/filter/occupancy.hpp"

namespace ogf::filter {

CellQuery queryCell(const BandedOgf& map, const CellKey& key) {
  const CellEstimate e = map.estimate(key);
  CellQuery q;
  q.key = key;
  q.mean = e.mean;
  q.variance = e.variance;
  q.allocated = e.allocated;
  q.occupancyProbability = occupancyProbability(e.mean);
  q.predictiveProbability = predictiveProbability(e.mean, e.variance);
  q.occupancyClass = occupancyClass(e.mean, map.config().occupiedThreshold, map.config().freeThreshold);
  q.entropyBits = binaryEntropyBits(q.predictiveProbability);
  return q;
}

Result<BoxSummary> summariseBox(const BandedOgf& map, const CellKey& lo, const CellKey& hi, std::size_t maxCells) {
  if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) {
    return Error{"box: lo must not exceed hi on any axis"};
  }
  const auto span = [](std::int32_t a, std::int32_t b) { return static_cast<double>(b) - static_cast<double>(a) + 1.0; };
  const double count = span(lo.x, hi.x) * span(lo.y, hi.y) * span(lo.z, hi.z);
  if (count > static_cast<double>(maxCells)) {
    return Error{"box: " + std::to_string(count) + " cells exceed the limit of " + std::to_string(maxCells)};
  }
  BoxSummary s;
  double varianceSum = 0.0;
  for (std::int32_t x = lo.x;; ++x) {
    for (std::int32_t y = lo.y;; ++y) {
      for (std::int32_t z = lo.z;; ++z) {
        const CellQuery q = queryCell(map, CellKey{x, y, z});
        ++s.cells;
        s.allocated += q.allocated ? 1U : 0U;
        s.occupied += q.occupancyClass > 0 ? 1U : 0U;
        s.free += q.occupancyClass < 0 ? 1U : 0U;
        s.unknown += q.occupancyClass == 0 ? 1U : 0U;
        s.entropyBits += q.entropyBits;
        varianceSum += q.variance;
        if (z == hi.z) {
          break;
        }
      }
      if (y == hi.y) {
        break;
      }
    }
    if (x == hi.x) {
      break;
    }
  }
  s.meanVariance = varianceSum / static_cast<double>(s.cells);
  return s;
}

}  // namespace ogf::filter
