// Random occupancy scenes for the filter tests: a ground truth of random boxes on a grid of 2-D or 3-D
// cells, and measurements of random cells drawn without repetition, y = the truth.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "ogf/filter/measurement.hpp"

namespace ogf::filter::testing {

struct RandomScene {
  std::vector<CellKey> cells;           // every cell of the grid, lexicographic
  std::vector<std::int8_t> truth;       // +1 occupied, -1 free, per cell
  std::vector<Measurement> samples;     // in the order to apply them

  // nx × ny × nz cells (nz = 1 for 2-D), `boxes` random occupied boxes, `count` samples.
  static RandomScene make(int nx, int ny, int nz, int boxes, std::size_t count, unsigned seed) {
    RandomScene s;
    std::mt19937 rng(seed);
    for (int x = 0; x < nx; ++x) {
      for (int y = 0; y < ny; ++y) {
        for (int z = 0; z < nz; ++z) {
          s.cells.push_back({x, y, z});
        }
      }
    }
    s.truth.assign(s.cells.size(), -1);
    for (int b = 0; b < boxes; ++b) {
      const int x0 = static_cast<int>(rng() % static_cast<unsigned>(nx));
      const int y0 = static_cast<int>(rng() % static_cast<unsigned>(ny));
      const int z0 = static_cast<int>(rng() % static_cast<unsigned>(nz));
      const int w = 1 + static_cast<int>(rng() % 5U);
      const int h = 1 + static_cast<int>(rng() % 5U);
      const int d = 1 + static_cast<int>(rng() % 3U);
      for (std::size_t c = 0; c < s.cells.size(); ++c) {
        const CellKey& k = s.cells[c];
        if (k.x >= x0 && k.x < x0 + w && k.y >= y0 && k.y < y0 + h && k.z >= z0 && k.z < z0 + d) {
          s.truth[c] = 1;
        }
      }
    }
    std::vector<std::size_t> order(s.cells.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      order[i] = i;
    }
    std::shuffle(order.begin(), order.end(), rng);
    order.resize(std::min(count, order.size()));
    for (std::size_t i : order) {
      s.samples.push_back({s.cells[i], s.truth[i]});
    }
    return s;
  }
};

}  // namespace ogf::filter::testing
