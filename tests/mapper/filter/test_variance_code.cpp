// The 16-bit variance ratio of compact storage: exact at the prior, within 2^-12 relative everywhere in its
// range, monotonic, and clamped (never 0, never NaN) outside it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ogf/filter/variance_code.hpp"

namespace ogf::filter {
namespace {

TEST(VarianceCode, ThePriorIsExactAndEveryRatioRoundsWithinATwoThousandthOfAPercent) {
  EXPECT_EQ(decodeVarianceRatio(encodeVarianceRatio(1.0F)), 1.0F);
  float worst = 0.0F;
  for (float r = 1.0F; r > 1e-9F; r *= 0.9993F) {
    const float back = decodeVarianceRatio(encodeVarianceRatio(r));
    worst = std::max(worst, std::abs(back - r) / r);
  }
  EXPECT_LE(worst, std::ldexp(1.0F, -12) * 1.0001F);
  EXPECT_GT(worst, std::ldexp(1.0F, -13)) << "the rounding is the stated one, not finer";
}

TEST(VarianceCode, CodesAreMonotonicAndEveryCodeRoundTrips) {
  for (unsigned c = 1; c <= 0xFFFFU; ++c) {
    const auto code = static_cast<std::uint16_t>(c);
    ASSERT_GT(decodeVarianceRatio(code), decodeVarianceRatio(static_cast<std::uint16_t>(c - 1))) << c;
    ASSERT_EQ(encodeVarianceRatio(decodeVarianceRatio(code)), code) << c;
  }
}

TEST(VarianceCode, OutOfRangeRatiosAreClamped) {
  EXPECT_EQ(encodeVarianceRatio(0.0F), 0);
  EXPECT_EQ(encodeVarianceRatio(-1.0F), 0);
  EXPECT_EQ(encodeVarianceRatio(std::nanf("")), 0);
  EXPECT_GT(decodeVarianceRatio(0), 0.0F);
  EXPECT_EQ(encodeVarianceRatio(5.0F), 0xFFFF);
  EXPECT_LT(decodeVarianceRatio(0xFFFF), 2.0F);
}

}  // namespace
}  // namespace ogf::filter
