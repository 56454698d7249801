// The fast published state equals the exact functions of occupancy.hpp everywhere: on random cells, on
// cells placed at the class thresholds and at the rounding boundaries of the quantised probability, and in
// the far tails.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "ogf/filter/inverse_mills.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/filter/published_state.hpp"

namespace ogf::filter {
namespace {

void expectSame(const PublishedStateRule& rule, double ro, double rf, double mean, double variance) {
  ASSERT_EQ(rule.occupancyClass(mean), occupancyClass(mean, ro, rf)) << "mean " << mean;
  ASSERT_EQ(rule.quantisedProbability(mean, variance), quantiseProbability(predictiveProbability(mean, variance)))
      << "mean " << mean << ", variance " << variance;
}

// The largest m with Φ(m) < p found by bisection on the exact Φ.
double belowInverseCdf(double p) {
  double lo = -10.0;
  double hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (normalCdf(mid) < p ? lo : hi) = mid;
  }
  return lo;
}

TEST(PublishedStateRule, EqualsTheExactClassAndQuantisedProbability) {
  for (const auto& [ro, rf] : {std::pair{0.65, 0.35}, std::pair{0.9, 0.1}, std::pair{0.5, 0.5}}) {
    const PublishedStateRule rule(ro, rf);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> mean(-12.0, 12.0);
    std::uniform_real_distribution<double> logVariance(-9.0, 1.5);
    for (int i = 0; i < 200000; ++i) {
      expectSame(rule, ro, rf, mean(rng), std::exp(logVariance(rng)));
    }
    // At the class thresholds: m = Φ⁻¹(r) found by bisection, and its neighbouring doubles.
    for (const double r : {ro, rf}) {
      const double lo = belowInverseCdf(r);
      double m = lo;
      for (int k = 0; k < 40; ++k, m = std::nextafter(m, 100.0)) {
        expectSame(rule, ro, rf, m, 0.5);
      }
      for (const double d : {1e-12, 1e-10, 1e-9, 2e-9, 1e-8}) {
        expectSame(rule, ro, rf, lo - d, 0.5);
        expectSame(rule, ro, rf, lo + d, 0.5);
      }
    }
  }
  // At rounding boundaries: Φ(z) = (k + 0.5) / 10000 for a spread of k, with variance 0 so z = m.
  const PublishedStateRule rule(0.65, 0.35);
  for (int k = 0; k < 10000; k += 37) {
    const double lo = belowInverseCdf((k + 0.5) / 10000.0);
    for (const double d : {0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9}) {
      expectSame(rule, 0.65, 0.35, lo + d, 0.0);
    }
  }
  // Tails and non-finite inputs.
  for (const double m : {-40.0, -9.5, -9.0, 9.0, 9.5, 40.0, std::numeric_limits<double>::infinity(),
                         -std::numeric_limits<double>::infinity()}) {
    expectSame(rule, 0.65, 0.35, m, 0.25);
  }
}

}  // namespace
}  // namespace ogf::filter
