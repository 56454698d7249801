// The OctoMap baseline: see octomap_baseline.hpp.
#include "ogf/eval/octomap_baseline.hpp"

#include <octomap/OcTree.h>

#include <cstdint>

namespace ogf::eval {
namespace {

constexpr std::int64_t kOctomapKeyOffset = 32768;  // OcTreeKey of coordinate 0 at any resolution (tree_max_val)

bool toOctomapKey(const CellKey& k, octomap::OcTreeKey& out) {
  const std::int64_t v[3] = {k.x + kOctomapKeyOffset, k.y + kOctomapKeyOffset, k.z + kOctomapKeyOffset};
  for (int i = 0; i < 3; ++i) {
    if (v[i] < 0 || v[i] > 65535) return false;
    out[static_cast<unsigned>(i)] = static_cast<octomap::key_type>(v[i]);
  }
  return true;
}

}  // namespace

OctomapBaseline::OctomapBaseline(double resolution) : tree_(std::make_unique<octomap::OcTree>(resolution)) {}
OctomapBaseline::OctomapBaseline(std::unique_ptr<octomap::OcTree> tree) : tree_(std::move(tree)) {}
OctomapBaseline::~OctomapBaseline() = default;
OctomapBaseline::OctomapBaseline(OctomapBaseline&&) noexcept = default;
OctomapBaseline& OctomapBaseline::operator=(OctomapBaseline&&) noexcept = default;

Result<OctomapBaseline> OctomapBaseline::load(const std::filesystem::path& bt_path) {
  auto tree = std::make_unique<octomap::OcTree>(0.1);
  if (!std::filesystem::exists(bt_path)) return Error{bt_path.string() + ": no such file"};
  if (!tree->readBinary(bt_path.string())) return Error{bt_path.string() + ": not a readable OctoMap binary tree (.bt)"};
  return OctomapBaseline(std::move(tree));
}

void OctomapBaseline::insert(std::span<const Measurement> measurements) {
  octomap::OcTreeKey key;
  for (const Measurement& m : measurements) {
    if (!toOctomapKey(m.key, key)) continue;
    tree_->updateNode(key, m.y == Measurement::kOccupied, /*lazy_eval=*/true);
  }
}

void OctomapBaseline::insertCloud(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& origin,
                                  double max_range_m) {
  octomap::Pointcloud cloud;
  cloud.reserve(points.size());
  for (const Eigen::Vector3d& p : points) {
    cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  tree_->insertPointCloud(cloud, octomap::point3d(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                                                  static_cast<float>(origin.z())),
                          max_range_m, /*lazy_eval=*/true);
}

void OctomapBaseline::finish() { tree_->updateInnerOccupancy(); }

CellEstimate OctomapBaseline::estimate(const CellKey& key) const {
  octomap::OcTreeKey k;
  if (!toOctomapKey(key, k)) return {};
  const octomap::OcTreeNode* node = tree_->search(k);
  if (node == nullptr) return {};
  CellEstimate e;
  e.probability = node->getOccupancy();
  e.cell_class = tree_->isNodeOccupied(node) ? 1 : -1;
  return e;
}

double OctomapBaseline::resolution() const { return tree_->getResolution(); }
std::size_t OctomapBaseline::leafCount() const { return tree_->getNumLeafNodes(); }

Status OctomapBaseline::write(const std::filesystem::path& bt_path) const {
  if (!tree_->writeBinaryConst(bt_path.string())) return Error{bt_path.string() + ": cannot write the OctoMap"};
  return okStatus();
}

}  // namespace ogf::eval
