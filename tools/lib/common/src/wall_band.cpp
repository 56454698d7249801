// The walls' height band of a map: see wall_band.hpp.
#include "ogf/tools/wall_band.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ogf::tools {
namespace {

std::int32_t layersFor(double metres, double resolution, std::int32_t least) {
  return std::max(least, static_cast<std::int32_t>(std::lround(metres / resolution)));
}

}  // namespace

WallBandFinder::WallBandFinder(double resolution_m)
    : resolution_(resolution_m > 0.0 ? resolution_m : 0.1),
      band_layers_(layersFor(kBandHeightM, resolution_, 1)),
      max_surface_layers_(layersFor(kMaxSurfaceThicknessM, resolution_, 2)),
      free_reach_layers_(layersFor(kFreeReachM, resolution_, 2)) {}

void WallBandFinder::addStarts(std::map<std::int32_t, std::int64_t>& steps,
                               std::span<const std::int32_t> layers) const {
  // A cell at layer z lies in the bands starting at z - band_layers_ + 1 .. z; a column counts once per band,
  // so the starts of its cells are merged into disjoint intervals first.
  std::int32_t from = 0, to = 0;
  bool open = false;
  for (const std::int32_t z : layers) {
    const std::int32_t a = z - band_layers_ + 1;
    if (open && a <= to + 1) {
      to = z;
      continue;
    }
    if (open) {
      ++steps[from];
      --steps[to + 1];
    }
    from = a;
    to = z;
    open = true;
  }
  if (open) {
    ++steps[from];
    --steps[to + 1];
  }
}

void WallBandFinder::addColumn(std::span<const ColumnCell> cells) {
  std::vector<std::int32_t> walls;  // the layers of the column's standing cells
  const auto freeWithin = [&](std::size_t from, std::int32_t lo, std::int32_t hi, int direction) {
    for (auto i = static_cast<std::ptrdiff_t>(from); i >= 0 && i < static_cast<std::ptrdiff_t>(cells.size());
         i += direction) {
      const ColumnCell& c = cells[static_cast<std::size_t>(i)];
      if (c.z < lo || c.z > hi) return false;
      if (c.cell_class < 0) return true;
    }
    return false;
  };
  std::size_t i = 0;
  while (i < cells.size()) {
    if (cells[i].cell_class <= 0) {
      ++i;
      continue;
    }
    // A run of occupied cells in consecutive layers: [cells[i], cells[j - 1]].
    std::size_t j = i + 1;
    while (j < cells.size() && cells[j].cell_class > 0 && cells[j].z == cells[j - 1].z + 1) ++j;
    const std::int32_t bottom = cells[i].z, top = cells[j - 1].z;
    const bool thin = top - bottom + 1 <= max_surface_layers_;
    const bool passed = (i > 0 && freeWithin(i - 1, bottom - free_reach_layers_, bottom - 1, -1)) ||
                        freeWithin(j, top + 1, top + free_reach_layers_, +1);
    const bool surface = thin && passed;
    for (std::size_t k = i; k < j; ++k) {
      ++(surface ? surface_cells_ : wall_cells_)[cells[k].z];
      if (!surface) walls.push_back(cells[k].z);
    }
    i = j;
  }
  addStarts(wall_column_steps_, walls);
}

WallBand WallBandFinder::makeBand(std::int32_t lo, std::int32_t hi, std::string reason) const {
  return WallBand{lo, hi, lo * resolution_, (hi + 1) * resolution_, std::move(reason)};
}

std::optional<WallBand> WallBandFinder::band() const {
  if (wall_cells_.empty() && surface_cells_.empty()) return std::nullopt;
  const auto count = [](const std::map<std::int32_t, std::int64_t>& m, std::int32_t z) -> std::int64_t {
    const auto it = m.find(z);
    return it == m.end() ? 0 : it->second;
  };
  const auto isSurface = [&](std::int32_t z) { return count(surface_cells_, z) > count(wall_cells_, z); };
  const auto metres = [&](std::int32_t layer) { return layer * resolution_; };

  std::int32_t lowest = std::numeric_limits<std::int32_t>::max(),
               highest = std::numeric_limits<std::int32_t>::min();
  for (const auto* m : {&wall_cells_, &surface_cells_}) {
    if (m->empty()) continue;
    lowest = std::min(lowest, m->begin()->first);
    highest = std::max(highest, m->rbegin()->first);
  }
  // Storeys: the runs of layers between floor and ceiling layers.
  std::vector<Storey> storeys;
  for (std::int32_t z = lowest; z <= highest; ++z) {
    if (isSurface(z)) continue;
    if (storeys.empty() || storeys.back().hi != z - 1) storeys.push_back({z, z, 0});
    storeys.back().hi = z;
    storeys.back().wall_cells += count(wall_cells_, z);
  }
  const auto storey = std::max_element(storeys.begin(), storeys.end(), [](const Storey& a, const Storey& b) {
    return a.wall_cells < b.wall_cells;
  });
  if (storey == storeys.end() || storey->wall_cells == 0) {
    // Nothing stands up between the surfaces: the band above the largest of them.
    const auto largest = std::max_element(surface_cells_.begin(), surface_cells_.end(),
                                          [](const auto& a, const auto& b) { return a.second < b.second; });
    return makeBand(largest->first + 1, largest->first + band_layers_,
                    fmt::format("no walls; above the largest horizontal surface, at {:.2f} m",
                                metres(largest->first + 1)));
  }

  // Columns with standing cells in the band starting at each layer from `first` to `last`.
  const auto columnsFrom = [&](const std::map<std::int32_t, std::int64_t>& steps, std::int32_t first,
                               std::int32_t last) {
    std::vector<std::int64_t> n(static_cast<std::size_t>(last - first + 1), 0);
    std::int64_t sum = 0;
    auto it = steps.begin();
    for (std::int32_t a = first; a <= last; ++a) {
      for (; it != steps.end() && it->first <= a; ++it) sum += it->second;
      n[static_cast<std::size_t>(a - first)] = sum;
    }
    return n;
  };
  std::string reason = storey->lo > lowest ? fmt::format("floor at {:.2f} m", metres(storey->lo - 1))
                                           : std::string("no floor below");
  if (storey->hi < highest) reason += fmt::format(", ceiling at {:.2f} m", metres(storey->hi + 1));
  if (storey->hi - storey->lo + 1 <= band_layers_)
    return makeBand(storey->lo, storey->hi, reason + "; the whole storey, lower than a band");

  // Each band scores the columns holding standing cells in it. From one start to the next the count moves by
  // a few percent with what each layer happened to catch, so the lowest start within kScoreTolerance of the
  // best wins: the low obstacles a robot meets stay in the picture. A surface covering less of its layer than
  // the walls do (a table top) is such an obstacle and stays in the band.
  const std::int32_t first = storey->lo, last = storey->hi - band_layers_ + 1;
  const auto walls = columnsFrom(wall_column_steps_, first, last);
  const double enough =
      (1.0 - kScoreTolerance) * static_cast<double>(*std::max_element(walls.begin(), walls.end()));
  std::size_t chosen = 0;
  while (static_cast<double>(walls[chosen]) < enough) ++chosen;
  const std::int32_t lo = first + static_cast<std::int32_t>(chosen);
  reason += fmt::format("; {} wall columns", walls[chosen]);
  return makeBand(lo, lo + band_layers_ - 1, std::move(reason));
}

PictureBand pictureBand(const std::optional<WallBand>& walls, std::optional<double> z_min,
                        std::optional<double> z_max, std::string_view source) {
  if (z_min && z_max) return {*z_min, *z_max, "set by --png-zmin and --png-zmax"};
  if (!walls) {
    PictureBand every{z_min.value_or(-1.0e9), z_max.value_or(1.0e9),
                      fmt::format("nothing occupied in {}: every layer", source)};
    if (z_min || z_max) every.why = fmt::format("set by --png-{}", z_min ? "zmin" : "zmax");
    return every;
  }
  const double height = walls->z_max - walls->z_min;
  if (z_min) {
    const double top = walls->z_max > *z_min ? walls->z_max : *z_min + height;
    return {*z_min, top, fmt::format("--png-zmin; the top from the walls' band of {}", source)};
  }
  if (z_max) {
    const double bottom = walls->z_min < *z_max ? walls->z_min : *z_max - height;
    return {bottom, *z_max, fmt::format("--png-zmax; the bottom from the walls' band of {}", source)};
  }
  return {walls->z_min, walls->z_max,
          fmt::format("the walls' band chosen from {}: {}", source, walls->reason)};
}

}  // namespace ogf::tools
