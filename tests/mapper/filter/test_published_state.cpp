// The fast published state equals the exact functions of occupancy.hpp everywhere: on random cells, on
// cells placed at the class thresholds and at the rounding boundaries of the quantised probability, and in
// the far tails.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

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

// The staged states of many cells (statesOf, as the change detection calls it on float means and
// variances) equal the exact functions: on random cells, on cells whose m/√(1+s) is within a few floats of
// a rounding boundary or whose mean is within a few floats of a class threshold, in the tails and on
// non-finite values; in runs longer than one stage.
TEST(PublishedStateRule, StatesOfManyCellsEqualTheExactClassAndQuantisedProbability) {
  const double ro = 0.65;
  const double rf = 0.35;
  const PublishedStateRule rule(ro, rf);
  std::vector<float> means;
  std::vector<float> variances;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> mean(-12.0, 12.0);
  std::uniform_real_distribution<double> logVariance(-21.0, 1.5);
  for (int i = 0; i < 100000; ++i) {
    means.push_back(static_cast<float>(mean(rng)));
    variances.push_back(static_cast<float>(std::exp(logVariance(rng))));
  }
  // Around rounding boundaries Φ(m/√(1+s)) = (k + 0.5)/10000: the nearest float mean and its neighbours.
  std::uniform_int_distribution<int> bucket(0, 9999);
  for (int i = 0; i < 3000; ++i) {
    const int k = i < 100 ? i : (i < 200 ? 9900 + (i - 100) : bucket(rng));
    const auto s = static_cast<float>(std::exp(logVariance(rng)));
    const double z = belowInverseCdf((k + 0.5) / 10000.0);
    float m = static_cast<float>(z * std::sqrt(1.0 + static_cast<double>(s)));
    m = std::nextafter(m, -100.0F);
    m = std::nextafter(m, -100.0F);
    for (int step = 0; step < 5; ++step, m = std::nextafter(m, 100.0F)) {
      means.push_back(m);
      variances.push_back(s);
    }
  }
  // Around the class thresholds.
  for (const double r : {ro, rf}) {
    float m = std::nextafter(std::nextafter(static_cast<float>(belowInverseCdf(r)), -100.0F), -100.0F);
    for (int step = 0; step < 5; ++step, m = std::nextafter(m, 100.0F)) {
      means.push_back(m);
      variances.push_back(0.5F);
    }
  }
  const float inf = std::numeric_limits<float>::infinity();
  for (const float m : {-40.0F, -9.5F, -9.0F, 9.0F, 9.5F, 40.0F, inf, -inf, std::nanf("")}) {
    for (const float s : {0.0F, 0.25F, 4.0F, inf}) {
      means.push_back(m);
      variances.push_back(s);
    }
  }
  // Both paths (four cells per AVX2 step where the CPU has it, the staged scalar code), and a length that
  // leaves a remainder after the last step of four.
  means.push_back(-0.5F);
  variances.push_back(0.5F);
  for (const bool avx2 : {true, false}) {
    const PublishedStateRule path(ro, rf, avx2);
    std::vector<PublishedState> states(means.size());
    path.statesOf(means, variances, states);
    for (std::size_t i = 0; i < means.size(); ++i) {
      const double m = static_cast<double>(means[i]);
      const double s = static_cast<double>(variances[i]);
      ASSERT_EQ(states[i].occupancyClass, occupancyClass(m, ro, rf)) << "mean " << m << ", variance " << s;
      ASSERT_EQ(states[i].quantisedProbability, quantiseProbability(predictiveProbability(m, s)))
          << "mean " << m << ", variance " << s << (avx2 ? " (AVX2 path)" : " (scalar path)");
      ASSERT_EQ(states[i], rule.stateOf(m, s));
    }
  }
}

}  // namespace
}  // namespace ogf::filter
