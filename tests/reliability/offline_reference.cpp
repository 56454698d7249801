#include "offline_reference.hpp"

#include "integration/scan_feeder.hpp"

namespace ogf::testing {

OfflineReference::OfflineReference(int points_per_scan)
    : points_(points_per_scan), mapper_(pipeline::ScanMapper::create(config_)), poses_(config_.fusion.pose_buffer) {
  if (mapper_.ok()) checksums_.push_back(mapper_->filter().checksum());
}

std::uint64_t OfflineReference::at(int updates) {
  while (mapper_.ok() && static_cast<int>(checksums_.size()) <= updates) {
    const auto step = feedStep(static_cast<int>(checksums_.size()) - 1, points_);
    for (const auto& p : step.poses)
      poses_.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                     Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
    const auto& s = step.scan;
    // Every scan is covered: its poses came with it.
    mapper_->measure({s.device_utime_start, s.x, s.y, s.z, s.time_offset_ns}, poses_);
    mapper_->apply(mapper_->measurements());
    checksums_.push_back(mapper_->filter().checksum());
  }
  return checksums_.empty() ? 0 : checksums_.at(static_cast<std::size_t>(updates));
}

}  // namespace ogf::testing
