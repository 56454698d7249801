// The OctoMap baseline ogf-eval scores beside the OGF: an octomap::OcTree at the map's resolution fed the
// very same per-scan measurements as the OGF (every cell a ray crossed a miss, the end cell a hit, one per
// cell per scan, occupied winning: what OcTree::insertPointCloud's computeUpdate gives, but with the
// deskewed rays of our own pipeline), with OctoMap's default sensor model (hit 0.7, miss 0.4, clamping
// 0.12/0.97). Only the inference differs: independent log-odds per cell against the OGF's correlated
// Gaussian filter. Classification is OctoMap's own: a known node is occupied when p > 0.5 (its default
// occupancy threshold), else free; a cell without a node is unknown (p = 0.5). A .bt file (from any
// source) can be loaded instead. CellKey (i, j, k) is OctoMap key (i + 32768, ...), the same cell bounds.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/core/cell_key.hpp>
#include <ogf/core/measurement.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <span>

#include "ogf/eval/map_scores.hpp"

namespace octomap {
class OcTree;
}

namespace ogf::eval {

class OctomapBaseline {
 public:
  explicit OctomapBaseline(double resolution);
  static Result<OctomapBaseline> load(const std::filesystem::path& bt_path);
  ~OctomapBaseline();
  OctomapBaseline(OctomapBaseline&&) noexcept;
  OctomapBaseline& operator=(OctomapBaseline&&) noexcept;

  // One scan's measurements (misses and hits), applied as OctoMap applies one point cloud.
  void insert(std::span<const Measurement> measurements);
  // One point cloud from one sensor origin through OctoMap's own OcTree::insertPointCloud (its ray casting,
  // its max-range cut), as a user of liboctomap maps a scan.
  void insertCloud(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& origin, double max_range_m);
  // Brings the inner nodes up to date after the inserts (they are deferred); call before write().
  void finish();
  CellEstimate estimate(const CellKey& key) const;
  double resolution() const;
  std::size_t leafCount() const;
  Status write(const std::filesystem::path& bt_path) const;

 private:
  explicit OctomapBaseline(std::unique_ptr<octomap::OcTree> tree);
  std::unique_ptr<octomap::OcTree> tree_;
};

}  // namespace ogf::eval
