// A certificate that the banded prior Σ0 = K ∘ T (cut at the stencil radius) is positive definite on every
// finite map, from its lattice spectrum: Σ0 is a convolution on the integer lattice, so for any finitely
// supported x, xᵀ Σ0 x = ∫ |x̂(ω)|² P(ω) dω / (2π)^d with P(ω) = Σ_o Σ0(o) cos(ω·o). If P > 0 on the torus,
// every principal submatrix is positive definite. The minimum of P is bounded from below by branch and
// bound over cells of ω with a Taylor bound (value, gradient, curvature) per cell, so the bound is
// rigorous; when it cannot be proven positive within a budget the result is ≤ 0 (not certified).
#pragma once

#include "ogf/filter/kernel.hpp"

namespace ogf::filter {

// A lower bound on min_ω P(ω) for the banded prior in `dimensions` (2 or 3).
// Positive means the prior is positive definite on every map.
double priorSpectrumLowerBound(const PriorCovariance& prior, int dimensions);

}  // namespace ogf::filter
