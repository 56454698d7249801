// Test helper: the map the daemon must hold, made offline: scan_feeder's scans 0..k-1 through a ScanMapper
// with the daemon's defaults, the filter checksum after each update (a daemon that mapped the same scans
// holds a bit-identical map, so equal checksums).
#pragma once

#include <cstdint>
#include <vector>

#include "ogf/fusion/pose_buffer.hpp"
#include "ogf/pipeline/scan_mapper.hpp"

namespace ogf::testing {

class OfflineReference {
 public:
  explicit OfflineReference(int points_per_scan);
  bool ok() const { return mapper_.ok(); }
  // The checksum after `updates` scans were mapped (0: the empty map); extended on demand.
  std::uint64_t at(int updates);

 private:
  int points_;
  pipeline::MapperConfig config_;  // the daemon's defaults
  Result<pipeline::ScanMapper> mapper_;
  fusion::PoseBuffer poses_;
  std::vector<std::uint64_t> checksums_;  // [k] after k updates
};

}  // namespace ogf::testing
