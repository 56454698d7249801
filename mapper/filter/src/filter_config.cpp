// Defaults and validation of FilterConfig.
#include "ogf/filter/filter_config.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace ogf::filter {
namespace {

Error fieldError(const char* field, double value, const char* why) {
  return Error{std::string("filter config: ") + field + " = " + std::to_string(value) + " " + why};
}

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

double defaultStencilRadius(double sigmaCells) {
  const double reach = 3.0 * sigmaCells;
  const double n = std::floor(reach * reach + 1e-9);
  return std::sqrt(std::max(1.0, n));
}

Result<FilterConfig> FilterConfig::resolved() const {
  FilterConfig c = *this;
  if (c.dimensions != 2 && c.dimensions != 3) {
    return fieldError("dimensions", c.dimensions, "must be 2 or 3");
  }
  if (!positiveFinite(c.resolution)) {
    return fieldError("resolution", c.resolution, "must be a positive number of metres");
  }
  if (!c.kernelSigma) {
    c.kernelSigma = c.resolution / 2.0;
  }
  if (!positiveFinite(*c.kernelSigma)) {
    return fieldError("kernelSigma", *c.kernelSigma, "must be a positive number of metres");
  }
  if (!c.kernelAmplitude) {
    c.kernelAmplitude = 1.0 / (*c.kernelSigma * std::sqrt(2.0 * std::numbers::pi));
  }
  if (!positiveFinite(*c.kernelAmplitude)) {
    return fieldError("kernelAmplitude", *c.kernelAmplitude, "must be positive");
  }
  if (!c.stencilRadius) {
    c.stencilRadius = defaultStencilRadius(*c.kernelSigma / c.resolution);
  }
  // The stencil must reach no further than the neighbouring block on each axis.
  if (!std::isfinite(*c.stencilRadius) || *c.stencilRadius < 1.0 ||
      *c.stencilRadius >= static_cast<double>(kBlockSide + 1)) {
    return fieldError("stencilRadius", *c.stencilRadius, "must lie in [1, 9) cells");
  }
  if (!c.taperSupport) {
    c.taperSupport = std::sqrt(std::floor(*c.stencilRadius * *c.stencilRadius + 1e-9) + 1.0);
  }
  if (!positiveFinite(*c.taperSupport)) {
    return fieldError("taperSupport", *c.taperSupport, "must be a positive number of cells");
  }
  if (!(c.freeThreshold > 0.0 && c.freeThreshold <= c.occupiedThreshold && c.occupiedThreshold < 1.0)) {
    return fieldError("occupiedThreshold", c.occupiedThreshold,
                      "must satisfy 0 < freeThreshold <= occupiedThreshold < 1");
  }
  if (!std::isfinite(c.skipTolerance) || c.skipTolerance < 0.0) {
    return fieldError("skipTolerance", c.skipTolerance, "must be >= 0");
  }
  if (c.threads < 1 || c.threads > 256) {
    return fieldError("threads", c.threads, "must lie in [1, 256]");
  }
  return c;
}

}  // namespace ogf::filter
