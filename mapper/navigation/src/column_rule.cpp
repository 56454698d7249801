#include "ogf/navigation/column_rule.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ogf::navigation {
namespace {

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation (relative error below 1.2e-9), refined by one
// Halley step on erfc.
double normalQuantile(double p) {
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                                 1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                                 6.680131188771972e+01,  -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                                 -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                                 3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  double x;
  if (p < kLow) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - kLow) {
    const double q = p - 0.5;
    const double r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  const double e = normalCdf(x) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

// The map's probabilities come quantised to 1/10000 (map_delta_t::PROBABILITY_SCALE), and the live grid
// costs a million band cells a scan at 0.1 m: Φ⁻¹ of each quantised value, computed once. A probability
// that is not exactly q/10000 is computed as it comes, so the result is the same either way.
constexpr int kQuantiles = 10000;
const std::array<double, kQuantiles + 1>& quantisedQuantiles() {
  static const auto table = [] {
    std::array<double, kQuantiles + 1> t{};
    for (int q = 1; q < kQuantiles; ++q) t[static_cast<std::size_t>(q)] = normalQuantile(q / double{kQuantiles});
    return t;
  }();
  return table;
}

double quantileOf(double p) {
  const long q = std::lround(p * kQuantiles);
  if (q > 0 && q < kQuantiles && static_cast<double>(q) / kQuantiles == p)
    return quantisedQuantiles()[static_cast<std::size_t>(q)];
  return normalQuantile(p);
}

// The rounded cost 100 · Φ(x) as Φ gives it: the reference costAtProbit's steps are found from.
std::int8_t roundedCost(double x) {
  return static_cast<std::int8_t>(std::lround(std::clamp(normalCdf(x), 0.0, 1.0) * 100));
}

// The smallest double x with roundedCost(x) > k, for k = 0..99, by bisection over the doubles between -10
// and 10 (Φ(-10) and 1 - Φ(10) are far below half a percent). A map of ordered doubles to integers makes
// every double in between a candidate, so each step is exact, not within some tolerance.
std::array<double, 100> costSteps() {
  const auto ordered = [](double x) {
    const auto bits = std::bit_cast<std::int64_t>(x);
    return bits < 0 ? std::numeric_limits<std::int64_t>::min() - bits : bits;
  };
  const auto unordered = [](std::int64_t o) {
    return std::bit_cast<double>(o < 0 ? std::numeric_limits<std::int64_t>::min() - o : o);
  };
  std::array<double, 100> steps{};
  for (int k = 0; k < 100; ++k) {
    std::int64_t lo = ordered(-10.0);  // roundedCost(lo) <= k
    std::int64_t hi = ordered(10.0);   // roundedCost(hi) > k
    // The distance between them passes 2^63: counted unsigned.
    for (std::uint64_t apart = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo); apart > 1;
         apart = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo)) {
      const std::int64_t mid = lo + static_cast<std::int64_t>(apart / 2);
      (roundedCost(unordered(mid)) > k ? hi : lo) = mid;
    }
    steps[static_cast<std::size_t>(k)] = unordered(hi);
  }
  return steps;
}

}  // namespace

std::int8_t costAtProbit(double x) {
  static const std::array<double, 100> steps = costSteps();
  // The steps at or below x: 7 comparisons where Φ would take an erfc (the live grid costs a million cells
  // a scan at 0.1 m).
  return static_cast<std::int8_t>(std::upper_bound(steps.begin(), steps.end(), x) - steps.begin());
}

std::int8_t cellCost(double predictive_probability, double variance) {
  const double p = std::clamp(std::isnan(predictive_probability) ? 0.5 : predictive_probability, 1e-4, 1 - 1e-4);
  const double s = std::isfinite(variance) && variance > 0 ? variance : 0.0;
  const double mean = quantileOf(p) * std::sqrt(1 + s);
  return costAtProbit(mean + std::sqrt(s));
}

NavColumn classifyColumn(std::span<const BandCell> cells, std::int32_t free_layers_needed) {
  std::int32_t free = 0;
  bool occupied = false;
  std::int8_t cost = 0;
  for (const auto& c : cells) {
    if (!c.known()) continue;
    occupied = occupied || c.cell_class == kClassOccupied;
    free += c.cell_class == kClassFree ? 1 : 0;
    cost = std::max(cost, c.cost);
  }
  if (occupied) return {cost, kClassOccupied};
  if (free >= std::max<std::int32_t>(free_layers_needed, 1)) return {cost, kClassFree};
  return {};
}

}  // namespace ogf::navigation
