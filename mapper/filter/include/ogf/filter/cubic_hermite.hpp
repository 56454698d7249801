// Cubic Hermite interpolation on a table of values and slopes at equally spaced nodes: Φ in
// published_state.hpp (λ in inverse_mills_table.hpp keeps the same cubics in powers of t).
#pragma once

#include <cstddef>
#include <cstdint>

namespace ogf::filter {

// The interpolant at `t` (in [0, 1]) of the way from node k to node k + 1: value[k] are the function's
// values, slope[k] its derivatives times the node spacing.
inline double cubicHermite(const double* value, const double* slope, std::size_t k, double t) {
  // Basis on [0, 1]: values v0, v1 with weights h00, h01; slopes d0, d1 with h10, h11.
  const double t2 = t * t;
  const double t3 = t2 * t;
  const double h01 = 3.0 * t2 - 2.0 * t3;
  const double h00 = 1.0 - h01;
  const double h10 = t3 - 2.0 * t2 + t;
  const double h11 = t3 - t2;
  return h00 * value[k] + h01 * value[k + 1] + h10 * slope[k] + h11 * slope[k + 1];
}

}  // namespace ogf::filter
