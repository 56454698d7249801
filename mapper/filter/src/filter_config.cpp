// Defaults and validation of FilterConfig.
#include "ogf/filter/filter_config.hpp"

#include "ogf/filter/prior_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace ogf::filter {
namespace {

Error fieldError(const char* field, double value, const char* why) {
  return Error::configuration(std::string("filter config: ") + field + " = " + std::to_string(value) + " " + why);
}

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

// Length of the shortest lattice offset the stencil leaves out, cells.
double shortestExcludedOffset(const StencilShape& shape, int dimensions) {
  const int reach = shape.reach() + 1;
  const int zReach = dimensions == 3 ? reach : 0;
  double best = static_cast<double>(reach);
  for (int x = -reach; x <= reach; ++x) {
    for (int y = -reach; y <= reach; ++y) {
      for (int z = -zReach; z <= zReach; ++z) {
        if (!shape.contains(CellKey{x, y, z})) {
          best = std::min(best, std::sqrt(static_cast<double>(x * x + y * y + z * z)));
        }
      }
    }
  }
  return best;
}

}  // namespace

double defaultStencilRadius(double sigmaCells) {
  if (sigmaCells <= 0.5 + 1e-9) {
    return std::sqrt(2.0);
  }
  const double reach = 4.0 * sigmaCells;
  return std::sqrt(std::floor(reach * reach + 1e-9));
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
  // The stencil must reach no further than the neighbouring block on each axis; in 3-D it is also kept
  // below 5 cells (515 neighbours, 1 KB per cell) so a configuration, or a map file header, cannot ask for
  // gigabytes per block.
  const double largestRadius = c.dimensions == 3 ? 5.0 : static_cast<double>(kBlockSide + 1);
  if (!std::isfinite(*c.stencilRadius) || *c.stencilRadius < 1.0 || *c.stencilRadius >= largestRadius) {
    return fieldError("stencilRadius", *c.stencilRadius,
                      c.dimensions == 3 ? "must lie in [1, 5) cells in 3-D" : "must lie in [1, 9) cells in 2-D");
  }
  const int largestManhattan = c.dimensions == 3 ? 4 : kBlockSide;
  if (c.stencilManhattanRadius < 0 || c.stencilManhattanRadius > largestManhattan) {
    return fieldError("stencilManhattanRadius", c.stencilManhattanRadius,
                      c.dimensions == 3 ? "must lie in [0, 4] cells in 3-D" : "must lie in [0, 8] cells in 2-D");
  }
  // The longest support that drops nothing: the shortest offset outside the stencil. Then Σ0 = K ∘ T
  // exactly and the Schur product theorem makes it positive definite; but T also damps the correlations
  // inside the band. Longer supports damp less and cut K ∘ T at the stencil, so they are taken only when
  // the lattice spectrum certifies the banded prior positive definite (prior_spectrum.hpp).
  const double shortest = shortestExcludedOffset(c.stencilShape(), c.dimensions);
  if (!c.taperSupport) {
    c.taperSupport = shortest;
    for (double factor : {64.0, 16.0, 8.0, 6.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.25}) {
      FilterConfig trial = c;
      trial.taperSupport = shortest * factor;
      if (priorSpectrumLowerBound(trial.prior(), c.dimensions) > 0.0) {
        c.taperSupport = trial.taperSupport;
        break;
      }
    }
  }
  if (!positiveFinite(*c.taperSupport)) {
    return fieldError("taperSupport", *c.taperSupport, "must be a positive number of cells");
  }
  if (*c.taperSupport > shortest + 1e-9 &&
      !(priorSpectrumLowerBound(c.prior(), c.dimensions) > 0.0)) {
    return fieldError("taperSupport", *c.taperSupport,
                      "leaves the banded prior not positive definite (its lattice spectrum reaches 0); use a "
                      "shorter support");
  }
  if (c.covariance != CovarianceStorage::kBanded && c.covariance != CovarianceStorage::kCompact) {
    return fieldError("covariance", static_cast<int>(c.covariance), "must be banded (0) or compact (1)");
  }
  if (auto policy = c.validatePolicy(); !policy) {
    return policy.error();
  }
  return c;
}

Status FilterConfig::validatePolicy() const {
  if (!(freeThreshold > 0.0 && freeThreshold <= occupiedThreshold && occupiedThreshold < 1.0)) {
    return fieldError("occupiedThreshold", occupiedThreshold, "must satisfy 0 < freeThreshold <= occupiedThreshold < 1");
  }
  if (!std::isfinite(skipTolerance) || skipTolerance < 0.0) {
    return fieldError("skipTolerance", skipTolerance, "must be >= 0");
  }
  if (!std::isfinite(clampZ) || clampZ < 0.0) {
    return fieldError("clampZ", clampZ, "must be >= 0 (0: never clamp)");
  }
  if (!std::isfinite(freeClampZ) || freeClampZ < 0.0) {
    return fieldError("freeClampZ", freeClampZ, "must be >= 0 (0: free measurements use clampZ)");
  }
  if (occupiedPriority != OccupiedPriority::kScan && occupiedPriority != OccupiedPriority::kMap) {
    return fieldError("occupiedPriority", static_cast<int>(occupiedPriority), "must be scan (0) or map (1)");
  }
  if (freeReleaseCount < 0 || freeReleaseCount > kMaxFreeRelease) {
    return fieldError("freeReleaseCount", freeReleaseCount, "must lie in [0, 127] scans (0: never)");
  }
  if (threads < 1 || threads > 256) {
    return fieldError("threads", threads, "must lie in [1, 256]");
  }
  return okStatus();
}

const char* toString(OccupiedPriority p) { return p == OccupiedPriority::kScan ? "scan" : "map"; }

std::optional<OccupiedPriority> parseOccupiedPriority(std::string_view text) {
  if (text == "scan") {
    return OccupiedPriority::kScan;
  }
  if (text == "map") {
    return OccupiedPriority::kMap;
  }
  return std::nullopt;
}

const char* toString(CovarianceStorage c) { return c == CovarianceStorage::kCompact ? "compact" : "banded"; }

std::optional<CovarianceStorage> parseCovarianceStorage(std::string_view text) {
  if (text == "banded") {
    return CovarianceStorage::kBanded;
  }
  if (text == "compact") {
    return CovarianceStorage::kCompact;
  }
  return std::nullopt;
}

}  // namespace ogf::filter
