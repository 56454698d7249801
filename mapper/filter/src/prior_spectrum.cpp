// Lattice spectrum of the banded prior, bounded from below by branch and bound over cells of frequency
// space: a cell is certified when P at its centre, minus the gradient and curvature terms of a Taylor bound
// over the cell, stays positive; otherwise it is split, up to a depth and an evaluation budget.
#include "ogf/filter/prior_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "ogf/filter/stencil.hpp"

namespace ogf::filter {
namespace {

struct Term {
  double x, y, z, weight;  // offset and 2·Σ0(offset) (the offset and its mirror)
};

struct Spectrum {
  double centre = 0.0;
  std::vector<Term> terms;
  double curvature = 0.0;  // bound on the largest eigenvalue of ∇²P: Σ |Σ0(o)| |o|²
  int dimensions = 3;
  long evaluations = 0;

  // P(ω) and |∇P(ω)|.
  void evaluate(const double w[3], double& value, double& slope) {
    evaluations += static_cast<long>(terms.size()) + 1;
    value = centre;
    double g[3] = {0.0, 0.0, 0.0};
    for (const Term& t : terms) {
      const double phase = w[0] * t.x + w[1] * t.y + w[2] * t.z;
      value += t.weight * std::cos(phase);
      const double s = -t.weight * std::sin(phase);
      g[0] += s * t.x;
      g[1] += s * t.y;
      g[2] += s * t.z;
    }
    slope = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  }

  // Lower bound of P over the cube of half-width `half` around `w` (refined where needed), or -1 when the
  // budget or depth runs out before P is certified positive there.
  double bound(const double w[3], double half, int depth) {
    double value = 0.0;
    double slope = 0.0;
    evaluate(w, value, slope);
    const double radius = half * std::sqrt(static_cast<double>(dimensions));
    const double lower = value - slope * radius - 0.5 * curvature * radius * radius;
    if (lower > 0.0 || value <= 0.0 || depth == 0 || evaluations > kBudget) {
      return value <= 0.0 ? value : (lower > 0.0 ? lower : -1.0);
    }
    double worst = value;
    const double h = half / 2.0;
    for (int i = 0; i < (dimensions == 3 ? 8 : 4); ++i) {
      const double c[3] = {w[0] + ((i & 1) != 0 ? h : -h), w[1] + ((i & 2) != 0 ? h : -h),
                           dimensions == 3 ? w[2] + ((i & 4) != 0 ? h : -h) : 0.0};
      worst = std::min(worst, bound(c, h, depth - 1));
      if (worst <= 0.0) {
        return worst;
      }
    }
    return worst;
  }

  static constexpr long kBudget = 3'000'000;  // term evaluations, a few milliseconds
};

}  // namespace

double priorSpectrumLowerBound(const PriorCovariance& prior, int dimensions) {
  constexpr int kGrid = 16;  // initial cells per axis
  const Stencil stencil(dimensions, prior.shape());
  Spectrum s;
  s.dimensions = dimensions;
  s.centre = prior.variance();
  for (const CellKey& o : stencil.forwardOffsets()) {
    const double w = prior(o);
    s.terms.push_back({static_cast<double>(o.x), static_cast<double>(o.y), static_cast<double>(o.z), 2.0 * w});
    s.curvature += 2.0 * std::abs(w) * static_cast<double>(o.x * o.x + o.y * o.y + o.z * o.z);
  }
  const double half = std::numbers::pi / kGrid;
  double lowest = s.centre;
  // First every coarse centre: a negative value there disproves definiteness at once.
  for (int kx = 0; kx < kGrid; ++kx) {
    for (int ky = 0; ky < kGrid; ++ky) {
      for (int kz = 0; kz < (dimensions == 3 ? kGrid : 1); ++kz) {
        const double w[3] = {(2 * kx + 1) * half, (2 * ky + 1) * half, dimensions == 3 ? (2 * kz + 1) * half : 0.0};
        double value = 0.0;
        double slope = 0.0;
        s.evaluate(w, value, slope);
        if (value <= 0.0) {
          return value;
        }
      }
    }
  }
  for (int kx = 0; kx < kGrid; ++kx) {
    for (int ky = 0; ky < kGrid; ++ky) {
      for (int kz = 0; kz < (dimensions == 3 ? kGrid : 1); ++kz) {
        const double w[3] = {(2 * kx + 1) * half, (2 * ky + 1) * half, dimensions == 3 ? (2 * kz + 1) * half : 0.0};
        lowest = std::min(lowest, s.bound(w, half, 10));
        if (lowest <= 0.0) {
          return lowest;
        }
      }
    }
  }
  return lowest;
}

}  // namespace ogf::filter
