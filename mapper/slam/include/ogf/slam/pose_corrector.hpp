// Pose correction per scan, the interface a mapper calls between odometry and its map: `none` passes
// odometry through, `scan-match` runs the scan matcher as improved odometry, `rbpf` runs grid-based
// FastSLAM. correct() returns the best estimate for the scan at once; correctedTrajectory() gives the
// estimate with hindsight (the best particle's whole history) for every scan seen.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam/grid_fastslam.hpp"
#include "ogf/slam/planar_scan.hpp"
#include "ogf/slam/pose2.hpp"

namespace ogf::slam {

enum class CorrectionMode { kNone, kScanMatch, kRbpf };

// "none", "scan-match", "rbpf".
Result<CorrectionMode> parseCorrectionMode(std::string_view text);
std::string_view toString(CorrectionMode mode);

struct PoseCorrectorConfig {
  CorrectionMode mode = CorrectionMode::kRbpf;
  // For kRbpf as given; for kScanMatch its particle count and sampling are overridden (one particle that
  // keeps the matcher's maximum).
  GridFastSlamConfig slam;

  Status validate() const;
};

class PoseCorrector {
 public:
  static Result<PoseCorrector> create(const PoseCorrectorConfig& config);

  // The corrected robot pose for a scan taken at odometry pose `odometry`. Scans are numbered from 0 in
  // call order.
  Pose2 correct(const Pose2& odometry, const PlanarScan& scan);

  std::uint64_t scansSeen() const { return next_scan_id_; }
  // The corrected pose of every scan seen, in call order, from the best particle's history: `odometry`
  // holds the poses passed to correct(), one per scan.
  std::vector<Pose2> correctedTrajectory(const std::vector<Pose2>& odometry) const;
  // The filter (absent in mode none).
  const GridFastSlam* slam() const { return slam_ ? &*slam_ : nullptr; }

 private:
  PoseCorrector() = default;

  std::optional<GridFastSlam> slam_;  // absent in mode none
  std::uint64_t next_scan_id_ = 0;
};

}  // namespace ogf::slam
