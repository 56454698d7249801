// The shared trajectory tree: iterative release, collection and the pose of scans between nodes.
#include "ogf/slam/trajectory.hpp"

#include <algorithm>

namespace ogf::slam {

TrajectoryNode::~TrajectoryNode() {
  // Walk up while this node holds the only reference to its parent, detaching each parent before it
  // dies so its destructor finds no chain to recurse into.
  std::shared_ptr<const TrajectoryNode> up = std::move(parent);
  while (up && up.use_count() == 1) {
    std::shared_ptr<const TrajectoryNode> next = std::move(const_cast<TrajectoryNode&>(*up).parent);
    up = std::move(next);
  }
}

std::vector<TrajectoryPoint> collectTrajectory(const std::shared_ptr<const TrajectoryNode>& head) {
  std::vector<TrajectoryPoint> out;
  for (const TrajectoryNode* n = head.get(); n != nullptr; n = n->parent.get()) {
    out.push_back({n->scan_id, n->pose, n->odometry});
  }
  std::reverse(out.begin(), out.end());
  return out;
}

Pose2 correctedPose(const std::vector<TrajectoryPoint>& points, std::uint64_t scan_id,
                    const Pose2& odometry) {
  auto it = std::upper_bound(points.begin(), points.end(), scan_id,
                             [](std::uint64_t id, const TrajectoryPoint& p) { return id < p.scan_id; });
  const TrajectoryPoint& k = it == points.begin() ? *it : *std::prev(it);
  return compose(k.pose, between(k.odometry, odometry));
}

}  // namespace ogf::slam
