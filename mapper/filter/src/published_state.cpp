// The published state of a cell: class thresholds in the latent space, and the tabulated Φ with exact
// fallbacks.
#include "ogf/filter/published_state.hpp"

#include <array>
#include <cmath>
#include <cstddef>

#include "ogf/filter/cubic_hermite.hpp"
#include "ogf/filter/inverse_mills.hpp"
#include "ogf/filter/occupancy.hpp"

namespace ogf::filter {
namespace {

constexpr double kLow = -9.0;  // Φ(−9)·10000 ≈ 1e-15: quantised to 0 below, to 10000 above +9
constexpr double kHigh = 9.0;
constexpr int kNodesPerUnit = 64;
constexpr double kSpacing = 1.0 / kNodesPerUnit;
constexpr auto kIntervals = static_cast<std::size_t>((kHigh - kLow) * kNodesPerUnit);
// Within this of Φ⁻¹(r) the class is decided by the exact comparison (Φ' ≥ 0.1 there for r in [0.01,
// 0.99]: 1e-9 in m is 1e-10 in Φ, far above the rounding of either computation).
constexpr double kClassBand = 1e-9;
// Within this of a rounding boundary (x.5 in units of 1e-4) the exact Φ decides; the table's error is
// about 1e-10 in Φ, 1e-6 in those units.
constexpr double kRoundingBand = 1e-4;

// Φ⁻¹(p) by bisection on the exact Φ: 200 halvings of [−40, 40] reach the spacing of doubles.
double inverseNormalCdf(double p) {
  double lo = -40.0;
  double hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 0.0; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) {
      break;
    }
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Φ and φ·spacing at the nodes, built once per process.
struct NormalCdfTable {
  std::array<double, kIntervals + 1> value{};
  std::array<double, kIntervals + 1> slope{};
  NormalCdfTable() {
    for (std::size_t k = 0; k < value.size(); ++k) {
      const double z = kLow + static_cast<double>(k) * kSpacing;
      value[k] = normalCdf(z);
      slope[k] = normalPdf(z) * kSpacing;
    }
  }
};

const NormalCdfTable& normalCdfTable() {
  static const NormalCdfTable table;
  return table;
}

}  // namespace

PublishedStateRule::PublishedStateRule(double occupiedThreshold, double freeThreshold)
    : occupiedThreshold_(occupiedThreshold), freeThreshold_(freeThreshold),
      occupiedZ_(inverseNormalCdf(occupiedThreshold)), freeZ_(inverseNormalCdf(freeThreshold)),
      value_(normalCdfTable().value.data()), slope_(normalCdfTable().slope.data()) {}

std::int8_t PublishedStateRule::occupancyClass(double mean) const {
  if (std::abs(mean - occupiedZ_) <= kClassBand || std::abs(mean - freeZ_) <= kClassBand || !std::isfinite(mean)) {
    return filter::occupancyClass(mean, occupiedThreshold_, freeThreshold_);
  }
  if (mean > occupiedZ_) {
    return 1;
  }
  return mean < freeZ_ ? std::int8_t{-1} : std::int8_t{0};
}

std::uint16_t PublishedStateRule::quantisedProbability(double mean, double variance) const {
  const double z = mean / std::sqrt(1.0 + variance);
  if (!(z >= kLow && z < kHigh)) {
    return quantiseProbability(predictiveProbability(mean, variance));
  }
  const double p = cubicHermite(value_, slope_, (z - kLow) * kNodesPerUnit);
  const double scaled = p * 10000.0;
  if (!(scaled >= 0.0 && scaled <= 10000.0)) {
    return quantiseProbability(predictiveProbability(mean, variance));
  }
  const auto whole = static_cast<std::uint16_t>(scaled);  // floor: scaled is not negative
  const double fraction = scaled - static_cast<double>(whole);
  if (std::abs(fraction - 0.5) < kRoundingBand) {
    return quantiseProbability(predictiveProbability(mean, variance));
  }
  return fraction < 0.5 ? whole : static_cast<std::uint16_t>(whole + 1);
}

}  // namespace ogf::filter
