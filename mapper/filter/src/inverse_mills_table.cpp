// The tabulated inverse Mills ratio: its nodes, computed once.
#include "ogf/filter/inverse_mills_table.hpp"

namespace ogf::filter {

namespace {
constexpr double kSpacing = 1.0 / InverseMillsTable::kNodesPerUnit;
constexpr auto kIntervals = static_cast<std::size_t>((InverseMillsTable::kHigh - InverseMillsTable::kLow) *
                                                     InverseMillsTable::kNodesPerUnit);
}  // namespace

InverseMillsTable::InverseMillsTable() {
  // λ and its slope at the nodes; dλ/dz = −λ(z + λ), times the spacing.
  std::vector<double> value(kIntervals + 1);
  std::vector<double> slope(kIntervals + 1);
  for (std::size_t k = 0; k < value.size(); ++k) {
    const double z = kLow + static_cast<double>(k) * kSpacing;
    value[k] = inverseMillsRatio(z);
    slope[k] = -value[k] * (z + value[k]) * kSpacing;
  }
  // The Hermite cubic of each interval (values v0, v1, slopes d0, d1 at its ends) in powers of t.
  coefficients_.resize(4 * kIntervals);
  for (std::size_t k = 0; k < kIntervals; ++k) {
    const double v0 = value[k];
    const double v1 = value[k + 1];
    const double d0 = slope[k];
    const double d1 = slope[k + 1];
    double* c = coefficients_.data() + 4 * k;
    c[0] = v0;
    c[1] = d0;
    c[2] = 3.0 * (v1 - v0) - 2.0 * d0 - d1;
    c[3] = 2.0 * (v0 - v1) + d0 + d1;
  }
}

const InverseMillsTable& inverseMillsTable() {
  static const InverseMillsTable table;
  return table;
}

}  // namespace ogf::filter
