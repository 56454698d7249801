// The inverse Mills ratio and the probit update stay accurate and finite far into both tails.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/inverse_mills.hpp"
#include "ogf/filter/inverse_mills_table.hpp"
#include "ogf/filter/probit_update.hpp"

namespace ogf::filter {
namespace {

// φ(z)/Φ(z) in long double (64-bit mantissa, exponent range to 1e±4932): an independent reference.
long double referenceMills(long double z) {
  const long double pdf = std::exp(-z * z / 2.0L) / std::sqrt(2.0L * 3.14159265358979323846264338327950288L);
  const long double cdf = 0.5L * std::erfc(-z / std::sqrt(2.0L));
  return pdf / cdf;
}

TEST(InverseMills, RelativeErrorBelow1e12OnMinus40To40) {
  double worst = 0.0;
  double worstZ = 0.0;
  for (int i = -40000; i <= 40000; ++i) {
    const double z = static_cast<double>(i) * 1e-3;
    const long double ref = referenceMills(static_cast<long double>(z));
    const double got = inverseMillsRatio(z);
    ASSERT_TRUE(std::isfinite(got)) << z;
    if (ref < static_cast<long double>(std::numeric_limits<double>::min())) {
      // λ below the smallest normal double (z > 37.5): only require it to be tiny and non-negative.
      EXPECT_GE(got, 0.0);
      EXPECT_LT(got, 1e-300);
      continue;
    }
    const double rel = static_cast<double>(std::fabs((static_cast<long double>(got) - ref) / ref));
    if (rel > worst) {
      worst = rel;
      worstZ = z;
    }
  }
  EXPECT_LT(worst, 1e-12) << "worst at z = " << worstZ;
}

TEST(InverseMills, ApproachesMinusZInTheFarLeftTail) {
  for (double z : {-1e3, -1e6, -1e12, -1e150}) {
    const double lambda = inverseMillsRatio(z);
    EXPECT_TRUE(std::isfinite(lambda));
    EXPECT_NEAR(lambda / -z, 1.0, 1e-6) << z;
  }
}

TEST(ProbitUpdate, ShrinkStaysInsideZeroToOneOverOnePlusS) {
  for (double mean : {-1e6, -50.0, -3.0, 0.0, 3.0, 50.0, 1e6}) {
    for (int y : {-1, 1}) {
      const ProbitUpdate u = probitUpdate(y, mean, 0.5);
      EXPECT_GE(u.covShrink, 0.0);
      EXPECT_LE(u.covShrink, 1.0 / 1.5);
      EXPECT_TRUE(std::isfinite(u.meanGain));
    }
  }
}

TEST(DenseOgf, CellMeasuredOneHundredThousandTimesStaysFinite) {
  Eigen::MatrixXd prior(2, 2);
  prior << 0.4, 0.2, 0.2, 0.4;
  for (int y : {-1, 1}) {
    DenseOgf ogf(prior);
    for (int k = 0; k < 100000; ++k) {
      ogf.update(0, y);
    }
    EXPECT_TRUE(ogf.mean().allFinite());
    EXPECT_TRUE(ogf.covariance().allFinite());
    EXPECT_GT(ogf.covariance()(0, 0), 0.0);
    EXPECT_GT(ogf.covariance()(1, 1), 0.0);
    EXPECT_EQ(ogf.mean()(0) > 0.0, y > 0);
    // Then the opposite measurement, far in the tail of λ: still finite, variance still positive.
    for (int k = 0; k < 1000; ++k) {
      ogf.update(0, -y);
    }
    EXPECT_TRUE(ogf.mean().allFinite());
    EXPECT_GT(ogf.covariance()(0, 0), 0.0);
  }
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

// The table the banded filter uses: within 1e-8 relative of the exact ratio on its range (dense samples,
// nodes and midpoints included), the exact ratio outside it.
TEST(InverseMillsTable, AgreesWithTheExactRatioOnItsRange) {
  const InverseMillsTable& table = inverseMillsTable();
  double worst = 0.0;
  double worstAt = 0.0;
  for (double z = InverseMillsTable::kLow; z < InverseMillsTable::kHigh; z += 1.0 / 1024.0 + 1e-7) {
    const double exact = inverseMillsRatio(z);
    const double rel = std::abs(table(z) - exact) / exact;
    if (rel > worst) {
      worst = rel;
      worstAt = z;
    }
  }
  EXPECT_LT(worst, 1e-8) << "at z = " << worstAt;
  EXPECT_GT(worst, 0.0);  // it is the table that was measured, not the exact function
  for (double z : {-40.0, -8.5, 4.0, 7.5, 30.0}) {
    EXPECT_EQ(table(z), inverseMillsRatio(z)) << z;
  }
}

}  // namespace
}  // namespace ogf::filter
