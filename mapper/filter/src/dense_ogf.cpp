// Dense OGF: the rank-1 form of eq. (5) on a full covariance.
#include "ogf/filter/dense_ogf.hpp"

#include <utility>

namespace ogf::filter {

DenseOgf::DenseOgf(std::vector<CellKey> cells, const std::function<double(const CellKey&)>& covariance)
    : cells_(std::move(cells)) {
  const auto n = static_cast<Eigen::Index>(cells_.size());
  mean_ = Eigen::VectorXd::Zero(n);
  cov_.resize(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    index_.emplace(cells_[static_cast<std::size_t>(i)], i);
    for (Eigen::Index j = 0; j < n; ++j) {
      cov_(i, j) = covariance(cells_[static_cast<std::size_t>(j)] - cells_[static_cast<std::size_t>(i)]);
    }
  }
}

DenseOgf::DenseOgf(Eigen::MatrixXd prior) : mean_(Eigen::VectorXd::Zero(prior.rows())), cov_(std::move(prior)) {}

Eigen::Index DenseOgf::indexOf(const CellKey& key) const {
  const auto it = index_.find(key);
  return it == index_.end() ? -1 : it->second;
}

ProbitUpdate DenseOgf::update(Eigen::Index index, int y) {
  const ProbitUpdate u = probitUpdate(y, mean_(index), cov_(index, index));
  const Eigen::VectorXd column = cov_.col(index);
  mean_ += column * u.meanGain;
  cov_.noalias() -= u.covShrink * (column * column.transpose());
  return u;
}

bool DenseOgf::update(const CellKey& key, int y) {
  const Eigen::Index i = indexOf(key);
  if (i < 0) {
    return false;
  }
  update(i, y);
  return true;
}

}  // namespace ogf::filter
