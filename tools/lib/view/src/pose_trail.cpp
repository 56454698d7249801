#include "ogf/view/pose_trail.hpp"

namespace ogf::view {

void PoseTrail::add(const fusion::Pose& pose) {
  ++poses_seen_;
  latest_ = pose;
  const std::array<float, 3> p{static_cast<float>(pose.position.x()), static_cast<float>(pose.position.y()),
                               static_cast<float>(pose.position.z())};
  if (points_.size() >= kTrailCapacity) return;
  if (!points_.empty()) {
    const auto& q = points_.back();
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    if (dx * dx + dy * dy + dz * dz < kTrailSpacing * kTrailSpacing) return;
  }
  points_.push_back(p);
}

}  // namespace ogf::view
