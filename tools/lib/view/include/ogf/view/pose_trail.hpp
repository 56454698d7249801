// Where the robot has been: body positions at least kTrailSpacing apart, up to kTrailCapacity points
// (further points are not kept; the robot marker still follows the latest pose).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "ogf/fusion/pose.hpp"

namespace ogf::view {

inline constexpr double kTrailSpacing = 0.05;        // metres
inline constexpr std::size_t kTrailCapacity = 100000;

class PoseTrail {
 public:
  void add(const fusion::Pose& pose);
  const std::optional<fusion::Pose>& latest() const { return latest_; }
  const std::vector<std::array<float, 3>>& points() const { return points_; }
  std::size_t posesSeen() const { return poses_seen_; }

 private:
  std::optional<fusion::Pose> latest_;
  std::vector<std::array<float, 3>> points_;
  std::size_t poses_seen_ = 0;
};

}  // namespace ogf::view
