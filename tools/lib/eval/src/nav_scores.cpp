#include "ogf/eval/nav_scores.hpp"

#include <fmt/format.h>

namespace ogf::eval {
namespace {

namespace nav = navigation;

double share(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

// The truth column (x, y) over `layers`: occupied, free, or nullopt (not scored).
std::optional<std::int8_t> truthColumn(const sim::GroundTruth& truth, std::int32_t x, std::int32_t y,
                                       const nav::LayerRange& layers) {
  bool all_free = true;
  for (std::int32_t z = layers.lo; z <= layers.hi; ++z) {
    const auto c = truth.at({x, y, z});
    if (c == sim::CellClass::Occupied) return nav::kClassOccupied;
    all_free = all_free && c == sim::CellClass::Free;
  }
  if (all_free) return nav::kClassFree;
  return std::nullopt;
}

}  // namespace

double NavScores::freeAsFree() const { return share(free_as_free, truth_free); }
double NavScores::freeAsOccupied() const { return share(free_as_occupied, truth_free); }
double NavScores::occupiedAsOccupied() const { return share(occupied_as_occupied, truth_occupied); }
double NavScores::occupiedAsFree() const { return share(occupied_as_free, truth_occupied); }
double NavScores::accuracy() const {
  return share(free_as_free + occupied_as_occupied, truth_free + truth_occupied);
}
double NavScores::coverage() const {
  return share(free_as_free + free_as_occupied + occupied_as_occupied + occupied_as_free, truth_free + truth_occupied);
}

NavScores scoreNavGrid(const sim::GroundTruth& truth, const nav::NavGrid& grid) {
  NavScores s;
  const auto layers = grid.band.layers(truth.resolution);
  for (std::int32_t iy = 0; iy < truth.size[1]; ++iy) {
    for (std::int32_t ix = 0; ix < truth.size[0]; ++ix) {
      const std::int32_t x = truth.min_key.x + ix, y = truth.min_key.y + iy;
      const auto t = truthColumn(truth, x, y, layers);
      if (!t) continue;
      const auto c = grid.at({x, y}).column_class;
      if (*t == nav::kClassFree) {
        ++s.truth_free;
        s.free_as_free += c == nav::kClassFree;
        s.free_as_occupied += c == nav::kClassOccupied;
      } else {
        ++s.truth_occupied;
        s.occupied_as_occupied += c == nav::kClassOccupied;
        s.occupied_as_free += c == nav::kClassFree;
      }
    }
  }
  return s;
}

std::string navScoreTable(const NavScores& s, const nav::NavGrid& grid) {
  const auto layers = grid.band.layers(grid.resolution);
  std::string out = fmt::format(
      "\n2-D navigation grid: {} m columns, band {:.2f} to {:.2f} m above the floor at z = {:.2f} m (layers {} to {})\n",
      grid.resolution, grid.band.min_height, grid.band.max_height, grid.band.floor_z, layers.lo, layers.hi);
  out += fmt::format("nav truth free columns      {:>7}  free {:.4f}  occupied {:.4f}  unknown {:.4f}\n", s.truth_free,
                     s.freeAsFree(), s.freeAsOccupied(), 1.0 - s.freeAsFree() - s.freeAsOccupied());
  out += fmt::format("nav truth occupied columns  {:>7}  occupied {:.4f}  free {:.4f}  unknown {:.4f}\n",
                     s.truth_occupied, s.occupiedAsOccupied(), s.occupiedAsFree(),
                     1.0 - s.occupiedAsOccupied() - s.occupiedAsFree());
  out += fmt::format("nav accuracy                {:.4f}  (columns classed as their truth; unknown counts as wrong)\n",
                     s.accuracy());
  out += fmt::format("nav coverage                {:.4f}  (columns classed at all)\n", s.coverage());
  return out;
}

}  // namespace ogf::eval
