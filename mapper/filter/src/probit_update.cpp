// One probit measurement update, eq. (5)/(7), computed with a stable inverse Mills ratio.
#include "ogf/filter/probit_update.hpp"

#include <algorithm>
#include <cmath>

#include "ogf/filter/inverse_mills.hpp"

namespace ogf::filter {

ProbitUpdate probitUpdate(int y, double mean, double variance) {
  const double scale = std::sqrt(1.0 + variance);
  const double z = static_cast<double>(y) * mean / scale;
  return probitUpdateAt(y, variance, z, inverseMillsRatio(z));
}

ProbitUpdate probitUpdateAt(int y, double variance, double z, double lambda) {
  const double scale = std::sqrt(1.0 + variance);
  ProbitUpdate u;
  u.z = z;
  u.lambda = lambda;
  u.meanGain = static_cast<double>(y) * lambda / scale;
  // λ(z+λ) lies in (0, 1) mathematically; clamp against rounding so the variance can never grow or vanish.
  const double shape = std::clamp(lambda * (z + lambda), 0.0, 1.0);
  u.covShrink = shape / (1.0 + variance);
  return u;
}

}  // namespace ogf::filter
