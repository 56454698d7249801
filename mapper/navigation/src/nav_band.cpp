#include "ogf/navigation/nav_band.hpp"

#include <cmath>
#include <string>

namespace ogf::navigation {
namespace {

// Layer edges computed from metres: a centre exactly on the band's edge is in the band, whatever the
// rounding of floor_z + height.
constexpr double kEdgeTolerance = 1e-9;

}  // namespace

LayerRange NavBand::layers(double resolution) const {
  const double lo = (floor_z + min_height) / resolution - 0.5;
  const double hi = (floor_z + max_height) / resolution - 0.5;
  return {static_cast<std::int32_t>(std::ceil(lo - kEdgeTolerance)),
          static_cast<std::int32_t>(std::floor(hi + kEdgeTolerance))};
}

std::int32_t NavBand::freeLayersNeeded(double resolution) const {
  const auto n = layers(resolution).count();
  const auto needed = static_cast<std::int32_t>(std::ceil(min_free_fraction * n - kEdgeTolerance));
  return needed < 1 ? 1 : needed;
}

Status NavBand::validate(double resolution) const {
  if (!std::isfinite(floor_z)) return Error::configuration("nav.floor_z: must be a finite number");
  if (!std::isfinite(min_height)) return Error::configuration("nav.min_height: must be a finite number");
  if (!std::isfinite(max_height)) return Error::configuration("nav.max_height: must be a finite number");
  if (!(min_height < max_height))
    return Error::configuration("nav.max_height: must be above nav.min_height (" + std::to_string(min_height) + " m)");
  if (!(min_free_fraction >= 0 && min_free_fraction <= 1))
    return Error::configuration("nav.min_free_fraction: must be 0 to 1");
  if (!(resolution > 0)) return Error::configuration("map.resolution: must be > 0");
  const auto n = layers(resolution).count();
  if (n < 1)
    return Error::configuration("nav.min_height, nav.max_height: the band holds no cell centre at " +
                                std::to_string(resolution) + " m cells; widen it");
  if (n > kMaxLayers)
    return Error::configuration("nav.min_height, nav.max_height: the band holds " + std::to_string(n) +
                                " layers of cells, more than " + std::to_string(kMaxLayers));
  return okStatus();
}

}  // namespace ogf::navigation
