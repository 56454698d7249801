// What one column of the band says to a planner: a class (occupied, free, unknown) and a cost.
//
// Class: occupied when any cell of the band is occupied (eq. (3) of Sun et al.: Φ(m) > r_o); free when none
// is and enough of its layers hold free cells (NavBand::min_free_fraction); unknown otherwise.
//
// Cost: the class alone throws away what the OGF knows beyond eq. (3), its posterior variance. A cell's
// cost is the occupancy probability one standard deviation above the filter's estimate, Φ(m + √s): a cell
// the filter is sure is free costs little, one it is unsure of costs more even when its mean says free. The
// deltas carry the predictive probability p = Φ(m/√(1+s)) and s, so m = Φ⁻¹(p)·√(1+s). A known column costs
// 100 × the largest cost of its band's known cells (0..100, the ROS OccupancyGrid scale); an unknown column
// costs kUnknownCost (-1, as in a ROS OccupancyGrid).
#pragma once

#include <cstdint>
#include <span>

namespace ogf::navigation {

inline constexpr std::int8_t kClassFree = -1;
inline constexpr std::int8_t kClassUnknown = 0;
inline constexpr std::int8_t kClassOccupied = 1;
inline constexpr std::int8_t kUnknownCost = -1;

// A band cell as the projection keeps it: its cost (0..100) and class; cost kUnknownCost when the cell was
// never allocated (the prior).
struct BandCell {
  std::int8_t cost = kUnknownCost;
  std::int8_t cell_class = kClassUnknown;
  bool known() const { return cost != kUnknownCost; }
};

struct NavColumn {
  std::int8_t cost = kUnknownCost;
  std::int8_t column_class = kClassUnknown;
  friend bool operator==(const NavColumn&, const NavColumn&) = default;
  bool known() const { return column_class != kClassUnknown; }
};

// 100 · Φ(Φ⁻¹(p)·√(1+s) + √s), rounded, for a cell of predictive probability p and variance s (p clamped
// to [1e-4, 1 − 1e-4], s < 0 or not finite read as 0).
std::int8_t cellCost(double predictive_probability, double variance);

// 100 · Φ(x), rounded (half away from zero): the cost of a cell whose probit one standard deviation above
// its estimate is x. Read from the 100 values of x where the rounded cost steps up, found once from
// Φ itself, so it equals the rounded Φ(x) for every x but NaN.
std::int8_t costAtProbit(double x);

// The column of `cells` (one per band layer, never-allocated ones unknown), given how many free layers
// make it free (NavBand::freeLayersNeeded).
NavColumn classifyColumn(std::span<const BandCell> cells, std::int32_t free_layers_needed);

}  // namespace ogf::navigation
