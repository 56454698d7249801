// A particle's pose history as a tree shared between particles (Montemerlo et al.'s FastSLAM trick, as in
// gmapping's TNode): each processed scan adds a node pointing at its parent, so resampling copies a
// pointer, not a history. Also: a pose for any scan between processed ones, from the last processed
// node and the odometry since.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ogf/slam/pose2.hpp"

namespace ogf::slam {

struct TrajectoryNode {
  Pose2 pose;      // corrected robot pose, map frame
  Pose2 odometry;  // the odometry pose of the same scan
  std::uint64_t scan_id = 0;
  std::shared_ptr<const TrajectoryNode> parent;

  TrajectoryNode(const Pose2& p, const Pose2& o, std::uint64_t id, std::shared_ptr<const TrajectoryNode> up)
      : pose(p), odometry(o), scan_id(id), parent(std::move(up)) {}
  // Releases a long chain iteratively: the default recursive release of a 10⁵-node history would
  // overflow the stack.
  ~TrajectoryNode();
  TrajectoryNode(const TrajectoryNode&) = delete;
  TrajectoryNode& operator=(const TrajectoryNode&) = delete;
};

struct TrajectoryPoint {
  std::uint64_t scan_id = 0;
  Pose2 pose;
  Pose2 odometry;
};

// The history ending at `head`, oldest first.
std::vector<TrajectoryPoint> collectTrajectory(const std::shared_ptr<const TrajectoryNode>& head);

// The corrected pose of scan `scan_id` taken at odometry pose `odometry`: the last point at or before
// the scan (the first point for an earlier scan) composed with the odometry motion since,
// pose_k ⊕ (odometry_k⁻¹ ⊕ odometry). `points` are sorted by scan_id and not empty.
Pose2 correctedPose(const std::vector<TrajectoryPoint>& points, std::uint64_t scan_id, const Pose2& odometry);

}  // namespace ogf::slam
