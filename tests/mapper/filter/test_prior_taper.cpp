// The tapered, banded prior is positive definite where the plainly truncated kernel is not (σ = 1 cell,
// R = 1…3; docs/filter.md §5.1), and the configuration refuses a taper support that would break definiteness.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

#include "ogf/filter/filter_config.hpp"
#include "ogf/filter/prior_spectrum.hpp"

namespace ogf::filter {
namespace {

double smallestEigenvalue(const std::vector<CellKey>& cells, const std::function<double(const CellKey&)>& cov) {
  const auto n = static_cast<Eigen::Index>(cells.size());
  Eigen::MatrixXd m(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      m(i, j) = cov(cells[static_cast<std::size_t>(j)] - cells[static_cast<std::size_t>(i)]);
    }
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues()(0);
}

std::vector<CellKey> grid(int n, int dimensions) {
  std::vector<CellKey> cells;
  for (int x = 0; x < n; ++x) {
    for (int y = 0; y < n; ++y) {
      for (int z = 0; z < (dimensions == 3 ? n : 1); ++z) {
        cells.push_back({x, y, z});
      }
    }
  }
  return cells;
}

class PriorTaper : public ::testing::TestWithParam<int> {};

TEST_P(PriorTaper, KeepsThePriorPositiveDefiniteWhereTruncationDoesNot) {
  const int dimensions = GetParam();
  const std::vector<CellKey> cells = grid(dimensions == 3 ? 7 : 16, dimensions);
  for (double radius : {1.0, std::sqrt(2.0), std::sqrt(3.0), 2.0, 3.0}) {
    FilterConfig config;
    config.dimensions = dimensions;
    config.resolution = 1.0;
    config.kernelSigma = 1.0;  // σ = 1 cell: strong correlations
    config.stencilRadius = radius;
    config.stencilManhattanRadius = 0;
    const auto resolved = config.resolved();
    ASSERT_TRUE(resolved.ok()) << resolved.error().message;
    const GaussianKernel kernel = resolved->kernel();
    const StencilShape shape = resolved->stencilShape();
    const double truncated = smallestEigenvalue(cells, [&](const CellKey& o) {
      return shape.contains(o) ? kernel(std::sqrt(static_cast<double>(squaredLength(o)))) : 0.0;
    });
    const PriorCovariance prior = resolved->prior();
    const double tapered = smallestEigenvalue(cells, [&](const CellKey& o) { return prior(o); });
    EXPECT_LT(truncated, 0.0) << "R = " << radius << ": the truncated kernel is definite here";
    EXPECT_GT(tapered, 0.0) << "R = " << radius << ", taper support " << *resolved->taperSupport;
    EXPECT_GT(priorSpectrumLowerBound(prior, dimensions), 0.0) << "R = " << radius;
  }
}

INSTANTIATE_TEST_SUITE_P(TwoAndThreeD, PriorTaper, ::testing::Values(2, 3));

TEST(PriorTaper, ConfigurationRefusesASupportThatBreaksDefiniteness) {
  FilterConfig config;
  config.resolution = 1.0;
  config.kernelSigma = 1.0;
  config.stencilRadius = 1.0;
  config.stencilManhattanRadius = 0;
  config.taperSupport = 1000.0;  // no tapering at all: the truncated kernel
  const auto resolved = config.resolved();
  ASSERT_FALSE(resolved.ok());
  EXPECT_NE(resolved.error().message.find("taperSupport"), std::string::npos);
}

TEST(FilterConfig, PaperValuesAreTheDefaults) {
  FilterConfig config;
  config.resolution = 0.2;
  const auto r = config.resolved();
  ASSERT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(*r->kernelSigma, 0.1);
  EXPECT_NEAR(*r->kernelAmplitude, 1.0 / (0.1 * std::sqrt(2.0 * 3.141592653589793)), 1e-12);
  EXPECT_DOUBLE_EQ(*r->stencilRadius, std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(r->occupiedThreshold, 0.65);
  EXPECT_DOUBLE_EQ(r->freeThreshold, 0.35);
}

TEST(FilterConfig, ErrorsNameTheField) {
  FilterConfig config;
  config.resolution = -1.0;
  ASSERT_FALSE(config.resolved().ok());
  EXPECT_NE(config.resolved().error().message.find("resolution"), std::string::npos);
  config = FilterConfig{};
  config.dimensions = 4;
  EXPECT_NE(config.resolved().error().message.find("dimensions"), std::string::npos);
  config = FilterConfig{};
  config.occupiedThreshold = 0.2;
  EXPECT_NE(config.resolved().error().message.find("occupiedThreshold"), std::string::npos);
  config = FilterConfig{};
  config.stencilRadius = 12.0;
  EXPECT_NE(config.resolved().error().message.find("stencilRadius"), std::string::npos);
  config = FilterConfig{};
  config.threads = 0;
  EXPECT_NE(config.resolved().error().message.find("threads"), std::string::npos);
}

}  // namespace
}  // namespace ogf::filter
