// The tabulated inverse Mills ratio: its nodes, computed once.
#include "ogf/filter/inverse_mills_table.hpp"

namespace ogf::filter {

namespace {
constexpr double kSpacing = 1.0 / InverseMillsTable::kNodesPerUnit;
constexpr auto kIntervals = static_cast<std::size_t>((InverseMillsTable::kHigh - InverseMillsTable::kLow) *
                                                     InverseMillsTable::kNodesPerUnit);
}  // namespace

InverseMillsTable::InverseMillsTable() {
  value_.resize(kIntervals + 1);
  slope_.resize(kIntervals + 1);
  for (std::size_t k = 0; k < value_.size(); ++k) {
    const double z = kLow + static_cast<double>(k) * kSpacing;
    const double lambda = inverseMillsRatio(z);
    value_[k] = lambda;
    slope_[k] = -lambda * (z + lambda) * kSpacing;  // dλ/dz = −λ(z + λ), times the spacing
  }
}

const InverseMillsTable& inverseMillsTable() {
  static const InverseMillsTable table;
  return table;
}

}  // namespace ogf::filter
