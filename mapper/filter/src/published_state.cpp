// The published state of a cell: class thresholds in the latent space, and the tabulated Φ with exact
// fallbacks.
#include "ogf/filter/published_state.hpp"

#include <algorithm>
#include <array>
#include <bit>
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
// 1.5·2^52: for |x| < 2^51, x + kRoundingShift is x rounded to the nearest integer, which is then the low
// bits of the sum; the integer parts below are taken so, not by a conversion to an integer and back,
// which would lengthen each cell's chain of dependent instructions.
constexpr double kRoundingShift = 6755399441055744.0;
// Cells per stage of statesOf: the table coordinates of this many cells are computed, then looked up.
constexpr std::size_t kStage = 256;

// The integer nearest x (|x| < 2^51) as x + kRoundingShift.
double shiftedRound(double x) { return x + kRoundingShift; }
std::int64_t integerOf(double shifted) {
  return std::bit_cast<std::int64_t>(shifted) - std::bit_cast<std::int64_t>(kRoundingShift);
}

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

// u: m/√(1+s) in node spacings from the first node.
double tableCoordinate(double mean, double variance) { return (mean / std::sqrt(1.0 + variance) - kLow) * kNodesPerUnit; }

// The state from u by the table (value, slope), and whether it is certainly the exact one: u outside the
// table, near a rounding boundary or within kClassBand of a class threshold (occupiedZ, freeZ) is not.
[[gnu::always_inline]] inline bool tableState(const double* value, const double* slope, double occupiedZ,
                                              double freeZ, double u, double mean, PublishedState& state) {
  // Not negated, so a NaN fails it too; then u is replaced by 0 so the look-up stays in the table.
  const bool inTable = u >= 0.0 && u < static_cast<double>(kIntervals);
  const double v = inTable ? u : 0.0;
  // The node below v: v − ½ rounded (a tie picks either node of an interval's end, both exact there).
  const double nodeShifted = shiftedRound(v - 0.5);
  const double t = v - (nodeShifted - kRoundingShift);
  const double scaled = cubicHermite(value, slope, static_cast<std::size_t>(integerOf(nodeShifted)), t) * 10000.0;
  const double roundedShifted = shiftedRound(scaled);
  // scaled minus its nearest integer, in [−½, ½]: near ±½ scaled is near a rounding boundary.
  const double fraction = scaled - (roundedShifted - kRoundingShift);
  state.quantisedProbability = static_cast<std::uint16_t>(integerOf(roundedShifted));
  state.occupancyClass = static_cast<std::int8_t>(static_cast<int>(mean > occupiedZ) - static_cast<int>(mean < freeZ));
  return inTable & (std::abs(fraction) <= 0.5 - kRoundingBand) & (std::abs(mean - occupiedZ) > kClassBand) &
         (std::abs(mean - freeZ) > kClassBand);
}

}  // namespace

PublishedStateRule::PublishedStateRule(double occupiedThreshold, double freeThreshold)
    : occupiedThreshold_(occupiedThreshold), freeThreshold_(freeThreshold),
      occupiedZ_(inverseNormalCdf(occupiedThreshold)), freeZ_(inverseNormalCdf(freeThreshold)),
      value_(normalCdfTable().value.data()), slope_(normalCdfTable().slope.data()) {}

std::int8_t PublishedStateRule::occupancyClass(double mean) const { return stateOf(mean, 0.0).occupancyClass; }

std::uint16_t PublishedStateRule::quantisedProbability(double mean, double variance) const {
  return stateOf(mean, variance).quantisedProbability;
}

PublishedState PublishedStateRule::stateOf(double mean, double variance) const {
  PublishedState state;
  return tableState(value_, slope_, occupiedZ_, freeZ_, tableCoordinate(mean, variance), mean, state) ? state : exactStateOf(mean, variance);
}

void PublishedStateRule::statesOf(std::span<const float> means, std::span<const float> variances,
                                  std::span<PublishedState> out) const {
  std::array<double, kStage> u{};
  std::array<bool, kStage> exact{};
  for (std::size_t begin = 0; begin < means.size(); begin += kStage) {
    const std::size_t n = std::min(kStage, means.size() - begin);
    const float* m = means.data() + begin;
    const float* s = variances.data() + begin;
    PublishedState* state = out.data() + begin;
    for (std::size_t i = 0; i < n; ++i) {
      u[i] = tableCoordinate(static_cast<double>(m[i]), static_cast<double>(s[i]));
    }
    bool anyExact = false;
    for (std::size_t i = 0; i < n; ++i) {
      exact[i] = !tableState(value_, slope_, occupiedZ_, freeZ_, u[i], static_cast<double>(m[i]), state[i]);
      anyExact |= exact[i];
    }
    if (anyExact) {
      for (std::size_t i = 0; i < n; ++i) {
        if (exact[i]) {
          state[i] = exactStateOf(static_cast<double>(m[i]), static_cast<double>(s[i]));
        }
      }
    }
  }
}

PublishedState PublishedStateRule::exactStateOf(double mean, double variance) const {
  return {quantiseProbability(predictiveProbability(mean, variance)),
          filter::occupancyClass(mean, occupiedThreshold_, freeThreshold_)};
}

}  // namespace ogf::filter
