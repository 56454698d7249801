// Weight normalisation, n_eff and low-variance resampling on constructed weights.
#include <gtest/gtest.h>

#include <cmath>
#include <ogf/slam/resampling.hpp>
#include <vector>

namespace ogf::slam {
namespace {

TEST(Resampling, NormalizedWeightsSumToOneAndFollowTheLogWeights) {
  const std::vector<double> l{std::log(1.0), std::log(3.0), std::log(4.0)};
  const std::vector<double> w = normalizedWeights(l);
  EXPECT_NEAR(w[0], 0.125, 1e-12);
  EXPECT_NEAR(w[1], 0.375, 1e-12);
  EXPECT_NEAR(w[2], 0.5, 1e-12);
}

TEST(Resampling, NormalizedWeightsSurviveHugeLogWeights) {
  const std::vector<double> w = normalizedWeights(std::vector<double>{-5000.0, -5001.0});
  EXPECT_NEAR(w[0], 1.0 / (1.0 + std::exp(-1.0)), 1e-12);
}

TEST(Resampling, GainTemperesTheWeights) {
  const std::vector<double> l{0.0, -10.0};
  EXPECT_LT(normalizedWeights(l, 1.0)[1], normalizedWeights(l, 0.1)[1]);
  EXPECT_NEAR(normalizedWeights(l, 0.1)[1], std::exp(-1.0) / (1.0 + std::exp(-1.0)), 1e-12);
}

TEST(Resampling, EffectiveSampleSizeIsNForEqualWeightsAndOneForADegenerateSet) {
  EXPECT_NEAR(effectiveSampleSize(std::vector<double>(8, 0.125)), 8.0, 1e-12);
  EXPECT_NEAR(effectiveSampleSize(std::vector<double>{0.0, 1.0, 0.0, 0.0}), 1.0, 1e-12);
  // Two of four particles share the weight: n_eff = 1 / (0.25 + 0.25) = 2.
  EXPECT_NEAR(effectiveSampleSize(std::vector<double>{0.5, 0.0, 0.5, 0.0}), 2.0, 1e-12);
}

TEST(Resampling, LowVarianceDrawsEachParticleFloorOrCeilOfNTimesItsWeight) {
  const std::vector<double> w{0.05, 0.4, 0.0, 0.3, 0.25};
  for (const double u : {0.0, 0.1, 0.5, 0.999999}) {
    const std::vector<std::size_t> drawn = lowVarianceResample(w, u);
    ASSERT_EQ(drawn.size(), w.size());
    EXPECT_TRUE(std::is_sorted(drawn.begin(), drawn.end()));
    std::vector<int> count(w.size(), 0);
    for (std::size_t i : drawn) ++count[i];
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double expected = w[i] * static_cast<double>(w.size());
      EXPECT_GE(count[i], static_cast<int>(std::floor(expected))) << "particle " << i << " u " << u;
      EXPECT_LE(count[i], static_cast<int>(std::ceil(expected))) << "particle " << i << " u " << u;
    }
    EXPECT_EQ(count[2], 0) << "a zero-weight particle is never drawn";
  }
}

TEST(Resampling, LowVarianceKeepsEveryParticleOnceForEqualWeights) {
  const std::vector<std::size_t> drawn = lowVarianceResample(std::vector<double>(6, 1.0 / 6.0), 0.37);
  EXPECT_EQ(drawn, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}));
}

}  // namespace
}  // namespace ogf::slam
