// The Occupancy Grid Filter on a full covariance, eq. (5): the reference the banded filter is tested
// against. O(N²) per measurement and O(N²) memory, so for small maps only (a few thousand cells). Double
// precision throughout.
#pragma once

#include <Eigen/Core>
#include <ogf/core/cell_key.hpp>

#include <functional>
#include <span>
#include <unordered_map>
#include <vector>

#include "ogf/filter/probit_update.hpp"

namespace ogf::filter {

class DenseOgf {
 public:
  // Prior N(0, Σ0) over `cells`, Σ0_ij = covariance(cells[j] − cells[i]).
  DenseOgf(std::vector<CellKey> cells, const std::function<double(const CellKey&)>& covariance);
  // Prior N(0, prior) over cells 0..n-1 (no keys).
  explicit DenseOgf(Eigen::MatrixXd prior);

  // One measurement y ∈ {-1, +1} on cell `index`, eq. (5). Returns the scalar update that was applied.
  ProbitUpdate update(Eigen::Index index, int y);
  // The same by key; false when the key is not one of the cells.
  bool update(const CellKey& key, int y);

  const Eigen::VectorXd& mean() const { return mean_; }
  const Eigen::MatrixXd& covariance() const { return cov_; }
  const std::vector<CellKey>& cells() const { return cells_; }
  // Index of a cell, or -1.
  Eigen::Index indexOf(const CellKey& key) const;

 private:
  std::vector<CellKey> cells_;
  std::unordered_map<CellKey, Eigen::Index, CellKeyHash> index_;
  Eigen::VectorXd mean_;
  Eigen::MatrixXd cov_;
};

}  // namespace ogf::filter
