// One probit measurement update, eq. (5)/(7), computed with a stable inverse Mills ratio.
#include "ogf/filter/probit_update.hpp"

#include <cmath>

#include "ogf/filter/inverse_mills.hpp"

namespace ogf::filter {

ProbitUpdate probitUpdate(int y, double mean, double variance) {
  const double inverseScale = 1.0 / std::sqrt(1.0 + variance);
  const double z = static_cast<double>(y) * mean * inverseScale;
  return probitUpdateScaled(y, inverseScale, z, inverseMillsRatio(z));
}

}  // namespace ogf::filter
