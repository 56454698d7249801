// Expectation Propagation for GP classification on the grid (the paper's Algorithm 1, Sec. V; GPML
// Alg. 3.5): one Gaussian site per measurement (a cell measured twice has two sites), cavity and moment
// matching by eq. (7)-(8), iterated until the sites stop moving. It is the accuracy oracle for the OGF:
// d(m_ogf, m_ep) of eq. (12). O(sweeps · M · N²): small maps only.
#pragma once

#include <Eigen/Core>

#include <span>

#include "ogf/common/result.hpp"

namespace ogf::filter {

struct EpSite {
  Eigen::Index cell = 0;  // index into the prior
  int y = 1;              // -1 free, +1 occupied
};

struct EpOptions {
  double tolerance = 1e-8;  // largest change of a site's natural parameters in a sweep, to stop
  int maxSweeps = 100;
};

struct EpPosterior {
  Eigen::VectorXd mean;
  Eigen::MatrixXd covariance;
  int sweeps = 0;
  bool converged = false;
};

class ExpectationPropagation {
 public:
  ExpectationPropagation(Eigen::MatrixXd prior, EpOptions options = {});
  // Error when a site's cell is out of range or y is not ±1, or the prior is not positive definite.
  Result<EpPosterior> run(std::span<const EpSite> sites) const;

 private:
  Eigen::MatrixXd prior_;
  EpOptions options_;
};

}  // namespace ogf::filter
