#include "offline_checksum.hpp"

#include "ogf/fusion/pose_buffer.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "scan_feeder.hpp"

namespace ogf::testing {

std::uint64_t offlineChecksum(int n, int points) {
  pipeline::MapperConfig cfg;
  auto mapper = pipeline::ScanMapper::create(cfg);
  if (!mapper.ok()) return 0;
  fusion::PoseBuffer poses(cfg.fusion.pose_buffer);
  for (int i = 0; i < n; ++i) {
    const FeedStep step = feedStep(i, points);
    for (const auto& p : step.poses)
      poses.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                    Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
    const auto& s = step.scan;
    if (mapper->measure({s.device_utime_start, s.x, s.y, s.z, s.time_offset_ns}, poses) != fusion::PoseCoverage::kCovered)
      return 0;
    mapper->apply(mapper->measurements());
  }
  return mapper->filter().checksum();
}

}  // namespace ogf::testing
