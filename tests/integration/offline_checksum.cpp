#include "offline_checksum.hpp"

#include "ogf/fusion/pose_buffer.hpp"
#include "ogf/pipeline/scan_mapper.hpp"
#include "scan_feeder.hpp"

namespace ogf::testing {

std::uint64_t offlineChecksum(int n, int points) {
  std::vector<FeedStep> steps;
  for (int i = 0; i < n; ++i) steps.push_back(feedStep(i, points));
  int broken = 0;
  const std::uint64_t checksum = offlineChecksumOf(steps, {}, &broken);
  return broken == 0 ? checksum : 0;
}

std::uint64_t offlineChecksumOf(const std::vector<FeedStep>& steps, const std::set<int>& skip, int* broken) {
  pipeline::MapperConfig cfg;
  auto mapper = pipeline::ScanMapper::create(cfg);
  if (!mapper.ok()) return 0;
  fusion::PoseBuffer poses(cfg.fusion.pose_buffer);
  if (broken != nullptr) *broken = 0;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const FeedStep& step = steps[i];
    for (const auto& p : step.poses)
      poses.insert({p.utime, {p.position[0], p.position[1], p.position[2]},
                    Eigen::Quaterniond(p.orientation[0], p.orientation[1], p.orientation[2], p.orientation[3])});
    if (skip.count(static_cast<int>(i)) != 0) continue;
    const auto& s = step.scan;
    const auto coverage = mapper->measure({s.device_utime_start, s.x, s.y, s.z, s.time_offset_ns}, poses);
    if (coverage == fusion::PoseCoverage::kBroken) {
      if (broken != nullptr) ++*broken;
      continue;
    }
    if (coverage != fusion::PoseCoverage::kCovered) return 0;
    mapper->apply(mapper->measurements());
  }
  return mapper->filter().checksum();
}

}  // namespace ogf::testing
