// The scalar part of one OGF measurement update, eq. (5), in the form docs/filter.md §3.1 derives. For a
// measurement y ∈ {-1, +1} on a cell with mean μ and variance s:
//   z = y·μ/√(1+s),  λ = φ(z)/Φ(z),
//   m ← m + Σ[:, i] · meanGain,            meanGain = y·λ/√(1+s)
//   Σ ← Σ − Σ[:, i]·Σ[:, i]ᵀ · covShrink,   covShrink = λ·(z+λ)/(1+s)
// The same numbers are the EP moments of eq. (7) (Theorem 1), so the dense OGF, the banded OGF and EP share
// this function.
#pragma once

#include <algorithm>

namespace ogf::filter {

struct ProbitUpdate {
  double z = 0.0;
  double lambda = 0.0;     // inverse Mills ratio at z
  double meanGain = 0.0;   // y·λ/√(1+s)
  double covShrink = 0.0;  // λ·(z+λ)/(1+s), in [0, 1/(1+s)]
};

// y must be -1 or +1; variance must be positive.
ProbitUpdate probitUpdate(int y, double mean, double variance);

// The same from r = 1/√(1+s), z = y·μ·r and λ(z), for a caller that has them already (the same numbers
// when λ is inverseMillsRatio(z)): inline, for the banded filter's inner loop. Multiplying by r instead
// of dividing by √(1+s) and (1+s) keeps two divisions off the path from one update to the next.
inline ProbitUpdate probitUpdateScaled(int y, double inverseScale, double z, double lambda) {
  ProbitUpdate u;
  u.z = z;
  u.lambda = lambda;
  u.meanGain = static_cast<double>(y) * lambda * inverseScale;
  // λ(z+λ) lies in (0, 1) mathematically; clamp against rounding so the variance can never grow or vanish.
  const double shape = std::clamp(lambda * (z + lambda), 0.0, 1.0);
  u.covShrink = shape * (inverseScale * inverseScale);
  return u;
}

}  // namespace ogf::filter
