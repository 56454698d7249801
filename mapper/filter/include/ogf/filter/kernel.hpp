// The prior covariance of the map, Σ0 = K ∘ T (docs/filter.md §5.2): the paper's Gaussian kernel (Sec. VI,
// k(x, x') = φ(‖x − x'‖; 0, σ²)) times a compactly supported positive-definite Wendland taper, cut at the
// stencil radius. The Schur product of two positive-definite matrices is positive definite, so the banded
// prior stays a valid covariance where the plainly truncated kernel does not.
#pragma once

#include <ogf/core/cell_key.hpp>

#include "ogf/filter/stencil_shape.hpp"

namespace ogf::filter {

// k(d) = amplitude · exp(−d²/2σ²), d and σ in metres. The paper's amplitude is 1/(σ√(2π)).
struct GaussianKernel {
  double sigma = 0.1;
  double amplitude = 3.989422804014327;
  double operator()(double distance) const;
};

// Wendland's ψ_{3,1}(r) = (1 − r)^4_+ (4r + 1), r = d / support: positive definite in R^3 (hence on any
// 2-D or 3-D lattice), C², zero from d = support on.
struct WendlandTaper {
  double support = 1.0;  // cells
  double operator()(double distanceCells) const;
};

// Σ0 between two cells `offset` apart: kernel × taper inside the stencil, 0 outside.
class PriorCovariance {
 public:
  PriorCovariance(GaussianKernel kernel, WendlandTaper taper, double resolution, StencilShape shape);
  double operator()(const CellKey& offset) const;
  double variance() const { return (*this)(CellKey{}); }
  bool inStencil(const CellKey& offset) const { return shape_.contains(offset); }
  const StencilShape& shape() const { return shape_; }

 private:
  GaussianKernel kernel_;
  WendlandTaper taper_;
  double resolution_;
  StencilShape shape_;
};

// Squared length of an integer offset, in cells².
inline long long squaredLength(const CellKey& o) {
  return static_cast<long long>(o.x) * o.x + static_cast<long long>(o.y) * o.y +
         static_cast<long long>(o.z) * o.z;
}

}  // namespace ogf::filter
