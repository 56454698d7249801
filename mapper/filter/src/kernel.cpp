// Gaussian kernel, Wendland taper and the banded prior covariance built from them.
#include "ogf/filter/kernel.hpp"

#include <cmath>
#include <utility>

namespace ogf::filter {

double GaussianKernel::operator()(double distance) const {
  return amplitude * std::exp(-distance * distance / (2.0 * sigma * sigma));
}

double WendlandTaper::operator()(double distanceCells) const {
  const double r = distanceCells / support;
  if (r >= 1.0) {
    return 0.0;
  }
  const double a = 1.0 - r;
  return a * a * a * a * (4.0 * r + 1.0);
}

PriorCovariance::PriorCovariance(GaussianKernel kernel, WendlandTaper taper, double resolution,
                                 StencilShape shape)
    : kernel_(kernel), taper_(taper), resolution_(resolution), shape_(shape) {}

double PriorCovariance::operator()(const CellKey& offset) const {
  if (!inStencil(offset)) {
    return 0.0;
  }
  const double cells = std::sqrt(static_cast<double>(squaredLength(offset)));
  return kernel_(cells * resolution_) * taper_(cells);
}

}  // namespace ogf::filter
