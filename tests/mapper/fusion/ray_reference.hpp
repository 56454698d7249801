// A brute-force reference for ray traversal, for the tests: every cell of the bounding box is tested
// against the segment with the half-open cell rule, and the cells found are ordered by where the segment
// enters them. Parameters are computed in long double; for inputs exact in binary with few bits (the
// dyadic rays the tests draw), equal crossing parameters stay equal and distinct ones stay distinct, so
// ties are decided exactly.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <vector>

namespace ogf {
// Readable CellKeys in GoogleTest failure messages.
inline void PrintTo(const CellKey& k, std::ostream* os) { *os << '(' << k.x << ", " << k.y << ", " << k.z << ')'; }
}  // namespace ogf

namespace ogf::fusion::test {

struct RayParameterBound {
  long double t = 0;
  bool open = false;
};

// Cells in which some point of [origin, endpoint] lies, in order of entry, without the endpoint's cell.
inline std::vector<CellKey> referenceRayCells(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint,
                                              double resolution) {
  std::array<long double, 3> u0{};
  std::array<long double, 3> u1{};
  std::array<std::int32_t, 3> lo{};
  std::array<std::int32_t, 3> hi{};
  for (Eigen::Index a = 0; a < 3; ++a) {
    // The same division as cellKeyOf, so both sides see the same cell-unit coordinates.
    const double c0 = origin[a] / resolution;
    const double c1 = endpoint[a] / resolution;
    const auto i = static_cast<std::size_t>(a);
    u0[i] = static_cast<long double>(c0);
    u1[i] = static_cast<long double>(c1);
    lo[i] = static_cast<std::int32_t>(std::floor(std::min(c0, c1)));
    hi[i] = static_cast<std::int32_t>(std::floor(std::max(c0, c1)));
  }
  struct Entry {
    CellKey cell;
    RayParameterBound entry;
  };
  std::vector<Entry> found;
  for (std::int32_t x = lo[0]; x <= hi[0]; ++x) {
    for (std::int32_t y = lo[1]; y <= hi[1]; ++y) {
      for (std::int32_t z = lo[2]; z <= hi[2]; ++z) {
        const std::array<std::int32_t, 3> c{x, y, z};
        RayParameterBound lower{0.0L, false};
        RayParameterBound upper{1.0L, false};
        bool empty = false;
        auto raise = [&](RayParameterBound b) {
          if (b.t > lower.t || (b.t == lower.t && b.open)) lower = b;
        };
        auto cap = [&](RayParameterBound b) {
          if (b.t < upper.t || (b.t == upper.t && b.open)) upper = b;
        };
        for (std::size_t a = 0; a < 3; ++a) {
          const long double b0 = static_cast<long double>(c[a]);
          const long double b1 = b0 + 1.0L;
          const long double d = u1[a] - u0[a];
          if (d == 0.0L) {
            if (!(b0 <= u0[a] && u0[a] < b1)) empty = true;
          } else if (d > 0.0L) {  // b0 <= u0 + t d < b1
            raise({(b0 - u0[a]) / d, false});
            cap({(b1 - u0[a]) / d, true});
          } else {  // b0 <= u0 + t d < b1 with d < 0
            raise({(b1 - u0[a]) / d, true});
            cap({(b0 - u0[a]) / d, false});
          }
        }
        const bool non_empty = lower.t < upper.t || (lower.t == upper.t && !lower.open && !upper.open);
        if (!empty && non_empty) found.push_back({{x, y, z}, lower});
      }
    }
  }
  std::sort(found.begin(), found.end(), [](const Entry& l, const Entry& r) {
    if (l.entry.t != r.entry.t) return l.entry.t < r.entry.t;
    return !l.entry.open && r.entry.open;
  });
  const CellKey end_cell = cellKeyOf(endpoint, resolution);
  std::vector<CellKey> cells;
  for (const Entry& e : found) {
    if (e.cell != end_cell) cells.push_back(e.cell);
  }
  return cells;
}

}  // namespace ogf::fusion::test
