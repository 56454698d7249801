// The banded filter against the dense reference: equal at a stencil covering the whole grid, within 0.5 %
// at the default stencil; its prior is positive definite thanks to the taper; and its map does not depend
// on the number of threads.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/inverse_mills_table.hpp"
#include "ogf/filter/occupancy.hpp"
#include "ogf/filter/probit_update.hpp"
#include "random_scene.hpp"

namespace ogf::filter {
namespace {

using testing::RandomScene;

BandedOgf makeBanded(FilterConfig config) {
  auto made = BandedOgf::create(config);
  EXPECT_TRUE(made.ok()) << (made.ok() ? "" : made.error().message);
  return std::move(made).value();
}

// Applies every sample to both filters, one at a time in the same order.
void applyBoth(const RandomScene& scene, BandedOgf& banded, DenseOgf& dense) {
  for (const Measurement& m : scene.samples) {
    banded.update(m);
    ASSERT_TRUE(dense.update(m.key, m.y));
  }
}

Eigen::VectorXd bandedMeans(const BandedOgf& banded, const std::vector<CellKey>& cells) {
  Eigen::VectorXd m(static_cast<Eigen::Index>(cells.size()));
  for (std::size_t i = 0; i < cells.size(); ++i) {
    m(static_cast<Eigen::Index>(i)) = banded.estimate(cells[i]).mean;
  }
  return m;
}

void expectEqualToDense(FilterConfig config, const RandomScene& scene) {
  config.occupiedPriority = OccupiedPriority::kScan;  // every measurement reaches eq. (5), as in the dense filter
  BandedOgf banded = makeBanded(config);
  const PriorCovariance prior = banded.prior();
  DenseOgf dense(scene.cells, [&](const CellKey& o) { return prior(o); });
  applyBoth(scene, banded, dense);
  const double scale = prior.variance();
  double worstMean = 0.0;
  double worstCov = 0.0;
  for (std::size_t i = 0; i < scene.cells.size(); ++i) {
    const auto a = static_cast<Eigen::Index>(i);
    worstMean = std::max(worstMean, std::abs(banded.estimate(scene.cells[i]).mean - dense.mean()(a)));
    for (std::size_t j = 0; j < scene.cells.size(); ++j) {
      const auto b = static_cast<Eigen::Index>(j);
      worstCov = std::max(worstCov,
                          std::abs(banded.covariance(scene.cells[i], scene.cells[j]) - dense.covariance()(a, b)));
    }
  }
  // Float storage: a few ulps of float per update, relative to the prior's scale.
  EXPECT_LT(worstMean, 1e-5 * std::max(1.0, dense.mean().cwiseAbs().maxCoeff()));
  EXPECT_LT(worstCov, 1e-5 * scale);
}

TEST(BandedOgf, FullStencilEqualsDenseIn2D) {
  FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;
  config.kernelSigma = 1.0;
  config.stencilRadius = std::sqrt(32.0);  // offsets up to (4, 4): the whole 5 × 5 grid
  config.skipTolerance = 0.0;
  config.clampZ = 0.0;
  expectEqualToDense(config, RandomScene::make(5, 5, 1, 3, 60, 1));  // cells measured repeatedly too
}

TEST(BandedOgf, FullStencilEqualsDenseIn3D) {
  FilterConfig config;
  config.resolution = 0.2;
  config.kernelSigma = 0.2;
  config.stencilRadius = std::sqrt(9.0 + 9.0 + 4.0);  // the whole 4 × 4 × 3 grid
  config.taperSupport = 4.8;  // within the first excluded shell: no certificate search needed
  config.skipTolerance = 0.0;
  config.clampZ = 0.0;
  RandomScene scene = RandomScene::make(4, 4, 3, 3, 48, 2);
  // Negative keys too: blocks on both sides of 0.
  for (CellKey& c : scene.cells) {
    c = c - CellKey{2, 2, 1};
  }
  for (Measurement& m : scene.samples) {
    m.key = m.key - CellKey{2, 2, 1};
  }
  expectEqualToDense(config, scene);
}

struct Agreement {
  double d = 0.0;        // eq. (12), ‖m_banded − m_dense‖ / ‖m_dense‖
  double classes = 0.0;  // fraction of cells in the same class, eq. (3)
};

Agreement compareDefaultStencil(FilterConfig config, const RandomScene& scene, double skipTolerance) {
  config.skipTolerance = skipTolerance;
  config.occupiedPriority = OccupiedPriority::kScan;  // as the dense filter
  if (skipTolerance == 0.0) {
    config.clampZ = 0.0;  // the exact filter
  }
  BandedOgf banded = makeBanded(config);
  const FilterConfig resolved = *config.resolved();
  const GaussianKernel kernel = resolved.kernel();
  // The reference: the untapered, untruncated kernel of the paper.
  DenseOgf dense(scene.cells, [&](const CellKey& o) {
    return kernel(std::sqrt(static_cast<double>(squaredLength(o))) * resolved.resolution);
  });
  applyBoth(scene, banded, dense);
  const Eigen::VectorXd mb = bandedMeans(banded, scene.cells);
  Agreement a;
  a.d = (mb - dense.mean()).norm() / dense.mean().norm();
  std::size_t same = 0;
  for (Eigen::Index i = 0; i < mb.size(); ++i) {
    same += occupancyClass(mb(i), 0.65, 0.35) == occupancyClass(dense.mean()(i), 0.65, 0.35) ? 1U : 0U;
  }
  a.classes = static_cast<double>(same) / static_cast<double>(mb.size());
  return a;
}

TEST(BandedOgf, DefaultStencilWithinHalfPercentOfDenseIn2D) {
  FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;  // σ = half a cell by default
  for (unsigned seed : {11U, 12U, 13U}) {
    const Agreement a = compareDefaultStencil(config, RandomScene::make(25, 25, 1, 12, 400, seed), 1e-4);
    EXPECT_LE(a.d, 0.005) << "seed " << seed;
    EXPECT_GE(a.classes, 0.995) << "seed " << seed;
  }
}

TEST(BandedOgf, DefaultStencilWithinHalfPercentOfDenseIn3D) {
  FilterConfig config;  // 3-D, 0.2 m cells, σ = 0.1 m
  for (unsigned seed : {21U, 22U}) {
    const Agreement a = compareDefaultStencil(config, RandomScene::make(12, 12, 6, 20, 600, seed), 1e-4);
    EXPECT_LE(a.d, 0.005) << "seed " << seed;
    EXPECT_GE(a.classes, 0.995) << "seed " << seed;
  }
}

// The 2-D scene with every sample measured `times` times in a row of passes, so later updates are smaller.
RandomScene repeatedScene(int times) {
  RandomScene scene = RandomScene::make(25, 25, 1, 12, 400, 5);
  const std::vector<Measurement> once = scene.samples;
  for (int k = 1; k < times; ++k) {
    scene.samples.insert(scene.samples.end(), once.begin(), once.end());
  }
  return scene;
}

TEST(BandedOgf, SkippingNegligibleUpdatesChangesDByLessThanATenthOfAPercent) {
  FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;
  const RandomScene scene = repeatedScene(5);
  const Agreement exact = compareDefaultStencil(config, scene, 0.0);
  const Agreement skipping = compareDefaultStencil(config, scene, 1e-4);
  EXPECT_LT(std::abs(skipping.d - exact.d), 0.001) << "exact " << exact.d << ", skipping " << skipping.d;
  EXPECT_GE(skipping.classes, 0.995);
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

TEST(BandedOgf, CellMeasuredOneHundredThousandTimesStaysFiniteInFloatStorage) {
  for (double tolerance : {0.0, 1e-4}) {
    for (int y : {-1, 1}) {
      FilterConfig config;
      config.skipTolerance = tolerance;
      if (tolerance == 0.0) {
        config.clampZ = 0.0;
      }
      BandedOgf map = makeBanded(config);
      const Measurement m{{3, 4, 5}, static_cast<std::int8_t>(y)};
      for (int k = 0; k < 100000; ++k) {
        map.update(m);
      }
      // Then the opposite reading, deep in the tail of λ.
      for (int k = 0; k < 100; ++k) {
        map.update(Measurement{{3, 4, 5}, static_cast<std::int8_t>(-y)});
      }
      bool finite = true;
      bool positive = true;
      map.forEachCell([&](const CellKey&, float mean, float var) {
        finite = finite && std::isfinite(mean) && std::isfinite(var);
        positive = positive && var > 0.0F;
      });
      EXPECT_TRUE(finite) << "tolerance " << tolerance << ", y " << y;
      EXPECT_TRUE(positive) << "tolerance " << tolerance << ", y " << y;
    }
  }
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

// Measures the cell until y·m/√(1+s) passes `z`, then returns whether one more measurement with `y` was
// applied (UpdateStats).
bool appliedBeyond(FilterConfig config, int y, double z) {
  BandedOgf map = makeBanded(config);
  const CellKey cell{3, 4, 5};
  const Measurement m{cell, static_cast<std::int8_t>(y)};
  for (int k = 0; k < 10000; ++k) {
    const CellEstimate e = map.estimate(cell);
    if (static_cast<double>(y) * e.mean / std::sqrt(1.0 + e.variance) > z) {
      break;
    }
    map.update(m);
  }
  return map.update(m).applied == 1;
}

TEST(BandedOgf, FreeMeasurementsOnConfidentlyFreeCellsAreClampedEarlier) {
  FilterConfig config;  // clampZ 3, freeClampZ 1.5
  config.skipTolerance = 0.0;
  EXPECT_FALSE(appliedBeyond(config, -1, 1.6));  // free, past the free clamp: skipped
  EXPECT_TRUE(appliedBeyond(config, 1, 1.6));    // occupied at the same confidence: applied
  EXPECT_FALSE(appliedBeyond(config, 1, 3.05));  // occupied past clampZ: skipped
  config.freeClampZ = 0.0;                       // free measurements use clampZ
  EXPECT_TRUE(appliedBeyond(config, -1, 1.6));
  config.clampZ = 0.0;                           // no clamping at all, whatever freeClampZ says
  config.freeClampZ = 1.5;
  EXPECT_TRUE(appliedBeyond(config, -1, 1.6));
}

// The effect of the free clamp against the dense filter, bounded: every sample measured 15 times, so free
// cells pass the clamp and later free measurements are skipped. The classes are what a user sees.
TEST(BandedOgf, FreeClampKeepsClassesAndBoundsD) {
  FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;
  const RandomScene scene = repeatedScene(15);
  FilterConfig noFreeClamp = config;
  noFreeClamp.freeClampZ = 0.0;
  const Agreement without = compareDefaultStencil(noFreeClamp, scene, 1e-4);
  const Agreement with = compareDefaultStencil(config, scene, 1e-4);
  EXPECT_GE(with.classes, 0.995) << "d " << with.d << " (without the free clamp " << without.d << ")";
  // d measures the means' magnitude, which the clamp stops growing on free cells (measured: 0.029 against
  // 0.0013 without it); held below the paper's own bound for OGF against EP, eq. (12).
  EXPECT_LT(with.d, 0.04) << "without the free clamp " << without.d;
}

}  // namespace
}  // namespace ogf::filter

namespace ogf::filter {
namespace {

// Compact covariance storage (mean and variance per cell, covariances rebuilt from the prior) against the
// same dense reference: d measured 0.9-1.0 % in 2-D and 2.0-2.1 % in 3-D (banded: 0.3 %), 2.95 % on the
// free clamp's repeated scene (banded 2.87 %); the classes differ on up to 1.4 % of the 3-D cells.
TEST(BandedOgf, CompactStorageStaysWithinTheBoundsOfTheDenseFilter) {
  FilterConfig flat;
  flat.dimensions = 2;
  flat.resolution = 1.0;
  flat.covariance = CovarianceStorage::kCompact;
  for (unsigned seed : {11U, 12U, 13U}) {
    const Agreement a = compareDefaultStencil(flat, RandomScene::make(25, 25, 1, 12, 400, seed), 1e-4);
    EXPECT_LE(a.d, 0.012) << "2-D seed " << seed;
    EXPECT_GE(a.classes, 0.995) << "2-D seed " << seed;
  }
  FilterConfig solid;
  solid.covariance = CovarianceStorage::kCompact;
  for (unsigned seed : {21U, 22U}) {
    const Agreement a = compareDefaultStencil(solid, RandomScene::make(12, 12, 6, 20, 600, seed), 1e-4);
    EXPECT_LE(a.d, 0.025) << "3-D seed " << seed;
    EXPECT_GE(a.classes, 0.98) << "3-D seed " << seed;
  }
  const Agreement repeated = compareDefaultStencil(flat, repeatedScene(15), 1e-4);
  EXPECT_LT(repeated.d, 0.04);
  EXPECT_GE(repeated.classes, 0.985);
}

// In compact storage the measured cell's own mean moves by exactly eq. (5)'s step, in the arithmetic the
// filter documents: s its stored variance, r = 1/√(1 + s), z = y·m·r, λ from the filter's table, and the
// mean gain y·λ·r in float times the cell's column entry s. Cells measured free 0 to 5 times first, so s
// takes several codes (the filter looks r up by code: a wrong entry moves the mean).
TEST(BandedOgf, CompactUpdateOfTheMeasuredCellIsEquationFive) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  BandedOgf filter = makeBanded(config);
  for (int frees = 0; frees <= 5; ++frees) {
    const CellKey cell{16 * frees, 0, 0};  // apart: no other cell's update reaches it
    for (int k = 0; k < frees; ++k) filter.update(Measurement{cell, Measurement::kFree});
    const CellEstimate before = filter.estimate(cell);
    const double r = 1.0 / std::sqrt(1.0 + before.variance);
    const double z = before.mean * r;  // y = +1
    const ProbitUpdate u = probitUpdateScaled(1, r, z, inverseMillsTable()(z));
    const float expected = static_cast<float>(before.mean) +
                           static_cast<float>(u.meanGain) * static_cast<float>(before.variance);
    filter.update(Measurement{cell, Measurement::kOccupied});
    EXPECT_EQ(static_cast<float>(filter.estimate(cell).mean), expected)
        << frees << " free measurements first";
  }
}

// A stencil of more than 64 cells (σ = one cell in 3-D: R = 4, 257 cells) takes the cell-by-cell path of the
// compact update. The taper that keeps such a banded prior definite already costs d ≈ 20 % here (measured:
// banded 0.226, compact 0.195; classes 0.968 and 0.976): compact storage is no farther from the dense filter.
TEST(BandedOgf, CompactStorageWithALargeStencil) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  config.kernelSigma = 0.2;  // one cell
  const Agreement a = compareDefaultStencil(config, RandomScene::make(10, 10, 5, 12, 300, 31), 1e-4);
  FilterConfig banded = config;
  banded.covariance = CovarianceStorage::kBanded;
  const Agreement b = compareDefaultStencil(banded, RandomScene::make(10, 10, 5, 12, 300, 31), 1e-4);
  EXPECT_LE(a.d, 1.05 * b.d) << "banded " << b.d;
  EXPECT_GE(a.classes, b.classes - 0.005) << "banded " << b.classes;
  EXPECT_GE(a.classes, 0.97);
}

// The covariance compact storage reports is the rebuilt one, Σ0_ab·(Σ_aa/Σ0)·(Σ_bb/Σ0), 0 beyond the stencil.
TEST(BandedOgf, CompactStorageCovarianceIsRebuiltFromThePrior) {
  FilterConfig config;
  config.covariance = CovarianceStorage::kCompact;
  BandedOgf map = makeBanded(config);
  map.update(Measurement{{0, 0, 0}, 1});
  map.update(Measurement{{1, 0, 0}, -1});
  const double v0 = map.prior().variance();
  const double a = map.estimate({0, 0, 0}).variance;
  const double b = map.estimate({1, 0, 0}).variance;
  EXPECT_LT(a, 0.9 * v0);
  EXPECT_NEAR(map.covariance({0, 0, 0}, {1, 0, 0}), map.prior()({1, 0, 0}) * (a / v0) * (b / v0), 1e-6 * v0);
  EXPECT_NEAR(map.covariance({1, 0, 0}, {0, 0, 0}), map.covariance({0, 0, 0}, {1, 0, 0}), 1e-12);
  EXPECT_EQ(map.covariance({0, 0, 0}, {5, 0, 0}), 0.0);
}

}  // namespace
}  // namespace ogf::filter
