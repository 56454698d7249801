// An OGF's answer for one cell: see map_estimate.hpp.
#include "ogf/eval/map_estimate.hpp"

#include <ogf/filter/map_queries.hpp>

namespace ogf::eval {

CellEstimate ogfEstimate(const filter::BandedOgf& map, const CellKey& key) {
  const auto q = filter::queryCell(map, key);
  return CellEstimate{q.occupancyClass, q.predictiveProbability};
}

}  // namespace ogf::eval
