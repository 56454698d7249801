// Lattice spectrum of the banded prior on a grid of frequencies, with a curvature bound between grid
// points.
#include "ogf/filter/prior_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "ogf/filter/stencil.hpp"

namespace ogf::filter {

double priorSpectrumLowerBound(const PriorCovariance& prior, int dimensions) {
  constexpr int kGrid = 32;  // frequencies 2πk/32 per axis
  const Stencil stencil(dimensions, prior.shape());
  std::vector<double> cosine(kGrid);
  for (int k = 0; k < kGrid; ++k) {
    cosine[static_cast<std::size_t>(k)] = std::cos(2.0 * std::numbers::pi * k / kGrid);
  }
  // P(ω) = Σ0(0) + 2 Σ_{forward o} Σ0(o) cos(ω·o); curvature bound Σ_o |Σ0(o)| |o|².
  struct Term {
    int x, y, z;
    double weight;
  };
  std::vector<Term> terms;
  double curvature = 0.0;
  for (const CellKey& o : stencil.forwardOffsets()) {
    const double w = prior(o);
    terms.push_back({o.x, o.y, o.z, 2.0 * w});
    curvature += 2.0 * std::abs(w) * static_cast<double>(o.x * o.x + o.y * o.y + o.z * o.z);
  }
  const double centre = prior.variance();
  const int zGrid = dimensions == 3 ? kGrid : 1;
  double lowest = centre + 1.0;
  auto wrap = [](int v) { return static_cast<std::size_t>(((v % kGrid) + kGrid) % kGrid); };
  for (int kx = 0; kx < kGrid; ++kx) {
    for (int ky = 0; ky < kGrid; ++ky) {
      for (int kz = 0; kz < zGrid; ++kz) {
        double p = centre;
        for (const Term& t : terms) {
          p += t.weight * cosine[wrap(kx * t.x + ky * t.y + kz * t.z)];
        }
        lowest = std::min(lowest, p);
      }
    }
  }
  // Between grid points: the true minimiser ω* has ∇P = 0, the nearest grid point is within h√d/2, and
  // |∇²P| ≤ Σ|Σ0(o)||o|², so min P ≥ grid minimum − ½ (h√d/2)² · curvature.
  const double h = 2.0 * std::numbers::pi / kGrid;
  const double reach2 = h * h * static_cast<double>(dimensions) / 4.0;
  return lowest - 0.5 * reach2 * curvature;
}

}  // namespace ogf::filter
