// One run of the paper's Sec. VI-A experiment: from a ground truth and a sequence of samples, the maps of
// occupancy grid mapping, EP (Algorithm 1) and the OGF (eq. 5, dense, the paper's filter), plus our banded
// OGF; the difference d of eq. (12) and the accuracies of eq. (13).
#pragma once

#include <Eigen/Core>

#include <span>
#include <string>

#include "ogf/paper2d/ground_truth.hpp"

namespace ogf::paper2d {

struct ExperimentOptions {
  double sigma = 1.0;  // grid units (Sec. VI-A)
  double occupiedThreshold = 0.65;
  double freeThreshold = 0.35;
  double epTolerance = 1e-6;
  int epMaxSweeps = 100;
  double bandedRadius = 0.0;  // stencil radius of the banded OGF, cells; 0: the library's default
};

struct ExperimentRun {
  std::size_t samples = 0;
  double dOgfEp = 0.0;        // eq. (12)
  double accuracyOg = 0.0;    // eq. (13), occupancy grid mapping
  double accuracyEp = 0.0;
  double accuracyOgf = 0.0;
  double accuracyBanded = 0.0;
  double dBandedOgf = 0.0;    // eq. (12) between the banded and the dense OGF
  double bandedTaperSupport = 0.0;  // cells, as resolved by the library
  int epSweeps = 0;
  bool epConverged = false;
  Eigen::VectorXd meanOgf;    // row-major cells
  Eigen::VectorXd meanEp;
  Eigen::VectorXd meanBanded;
  std::vector<std::int8_t> classOg;
};

// Error message in `error` when EP or the banded filter fails.
bool runExperiment(const GroundTruth& truth, std::span<const Sample> samples, const ExperimentOptions& options,
                   ExperimentRun& run, std::string& error);

// Eq. (3) for a latent mean.
std::int8_t classify(double mean, const ExperimentOptions& options);

}  // namespace ogf::paper2d
