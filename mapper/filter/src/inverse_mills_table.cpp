// The tabulated inverse Mills ratio: nodes, and the cubic Hermite interpolation between them.
#include "ogf/filter/inverse_mills_table.hpp"

#include "ogf/filter/inverse_mills.hpp"

#include <cstddef>

namespace ogf::filter {

namespace {
constexpr double kSpacing = 1.0 / InverseMillsTable::kNodesPerUnit;
constexpr std::size_t kIntervals = static_cast<std::size_t>((InverseMillsTable::kHigh - InverseMillsTable::kLow) *
                                            InverseMillsTable::kNodesPerUnit);
}  // namespace

InverseMillsTable::InverseMillsTable() {
  value_.resize(kIntervals + 1);
  slope_.resize(kIntervals + 1);
  for (std::size_t k = 0; k < value_.size(); ++k) {
    const double z = kLow + static_cast<double>(k) * kSpacing;
    const double lambda = inverseMillsRatio(z);
    value_[k] = lambda;
    slope_[k] = -lambda * (z + lambda) * kSpacing;  // dλ/dz (GPML eq. 3.85's derivative), per interval
  }
}

double InverseMillsTable::operator()(double z) const {
  if (!(z >= kLow && z < kHigh)) {
    return inverseMillsRatio(z);
  }
  const double u = (z - kLow) * kNodesPerUnit;
  const auto k = static_cast<std::size_t>(u);
  const double t = u - static_cast<double>(k);
  // Hermite basis on [0, 1]: values v0, v1 with weights h00, h01; slopes d0, d1 with h10, h11.
  const double t2 = t * t;
  const double t3 = t2 * t;
  const double h01 = 3.0 * t2 - 2.0 * t3;
  const double h00 = 1.0 - h01;
  const double h10 = t3 - 2.0 * t2 + t;
  const double h11 = t3 - t2;
  return h00 * value_[k] + h01 * value_[k + 1] + h10 * slope_[k] + h11 * slope_[k + 1];
}

const InverseMillsTable& inverseMillsTable() {
  static const InverseMillsTable table;
  return table;
}

}  // namespace ogf::filter
