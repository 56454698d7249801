// The three mapping methods of Sec. VI-A and the banded OGF on one sample sequence.
#include "ogf/paper2d/experiment.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/dense_ogf.hpp"
#include "ogf/filter/expectation_propagation.hpp"
#include "ogf/filter/occupancy.hpp"

namespace ogf::paper2d {
namespace {

double accuracy(const GroundTruth& truth, const std::vector<std::int8_t>& classes) {
  std::size_t right = 0;
  for (std::size_t i = 0; i < truth.cells(); ++i) {
    right += classes[i] == truth.occupancy[i] ? 1U : 0U;
  }
  return static_cast<double>(right) / static_cast<double>(truth.cells());
}

std::vector<std::int8_t> classes(const Eigen::VectorXd& mean, const ExperimentOptions& options) {
  std::vector<std::int8_t> out;
  for (Eigen::Index i = 0; i < mean.size(); ++i) {
    out.push_back(classify(mean(i), options));
  }
  return out;
}

}  // namespace

std::int8_t classify(double mean, const ExperimentOptions& options) {
  return filter::occupancyClass(mean, options.occupiedThreshold, options.freeThreshold);
}

bool runExperiment(const GroundTruth& truth, std::span<const Sample> samples, const ExperimentOptions& options,
                   ExperimentRun& run, std::string& error) {
  const auto n = static_cast<Eigen::Index>(truth.cells());
  // The paper's kernel, k = φ(‖x − x'‖; 0, σ²), distances in grid units.
  const double amplitude = 1.0 / (options.sigma * std::sqrt(2.0 * std::numbers::pi));
  Eigen::MatrixXd prior(n, n);
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index b = 0; b < n; ++b) {
      const double dr = static_cast<double>(a / truth.cols - b / truth.cols);
      const double dc = static_cast<double>(a % truth.cols - b % truth.cols);
      prior(a, b) = amplitude * std::exp(-(dr * dr + dc * dc) / (2.0 * options.sigma * options.sigma));
    }
  }
  run = ExperimentRun{};
  run.samples = samples.size();

  // Occupancy grid mapping with noise-free samples: a sampled cell is what it was measured, others unknown.
  run.classOg.assign(truth.cells(), 0);
  std::vector<filter::EpSite> sites;
  filter::DenseOgf dense(prior);
  filter::FilterConfig config;
  config.dimensions = 2;
  config.resolution = 1.0;
  config.kernelSigma = options.sigma;
  config.occupiedThreshold = options.occupiedThreshold;
  config.freeThreshold = options.freeThreshold;
  config.occupiedPriority = filter::OccupiedPriority::kScan;  // every sample reaches eq. (5), as in the dense filter
  if (options.bandedRadius > 0.0) {
    config.stencilRadius = options.bandedRadius;
  }
  auto banded = filter::BandedOgf::create(config);
  if (!banded) {
    error = banded.error().message;
    return false;
  }
  for (const Sample& s : samples) {
    const Eigen::Index i = s.row * truth.cols + s.col;
    run.classOg[static_cast<std::size_t>(i)] = s.y;
    sites.push_back({i, s.y});
    dense.update(i, s.y);
    banded->update(filter::Measurement{CellKey{s.col, s.row, 0}, s.y});
  }
  const auto ep = filter::ExpectationPropagation(prior, {options.epTolerance, options.epMaxSweeps}).run(sites);
  if (!ep) {
    error = ep.error().message;
    return false;
  }
  run.bandedTaperSupport = *banded->config().taperSupport;
  run.meanOgf = dense.mean();
  run.meanEp = ep->mean;
  run.epSweeps = ep->sweeps;
  run.epConverged = ep->converged;
  run.meanBanded.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    run.meanBanded(i) =
        banded->estimate(CellKey{static_cast<int>(i % truth.cols), static_cast<int>(i / truth.cols), 0}).mean;
  }
  const double epNorm = run.meanEp.norm();
  run.dOgfEp = epNorm > 0.0 ? (run.meanOgf - run.meanEp).norm() / epNorm : 0.0;
  const double ogfNorm = run.meanOgf.norm();
  run.dBandedOgf = ogfNorm > 0.0 ? (run.meanBanded - run.meanOgf).norm() / ogfNorm : 0.0;
  run.accuracyOg = accuracy(truth, run.classOg);
  run.accuracyEp = accuracy(truth, classes(run.meanEp, options));
  run.accuracyOgf = accuracy(truth, classes(run.meanOgf, options));
  run.accuracyBanded = accuracy(truth, classes(run.meanBanded, options));
  return true;
}

}  // namespace ogf::paper2d
