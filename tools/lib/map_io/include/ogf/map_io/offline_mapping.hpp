// The offline run behind ogf-map: the whole odometry loaded first (a file holds it all, so nothing has to
// wait for poses), then every scan placed with the poses at its points' times (or from a fixed pose for a
// tripod, or from a PCD's viewpoint), turned into measurements and folded into the filter through the same
// pipeline::ScanMapper the daemon runs. A scan the odometry does not cover is counted and left out: never
// extrapolated.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/correction/scan_pose_correction.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/persistence/map_pager.hpp>
#include <ogf/pipeline/scan_mapper.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "ogf/map_io/scan_record.hpp"

namespace ogf::map_io {

struct OfflineCounts {
  std::int64_t scans_in = 0;         // scans offered
  std::int64_t scans_mapped = 0;     // folded into the map
  std::int64_t scans_uncovered = 0;  // outside the odometry's time span, left out
  std::int64_t scans_empty = 0;      // no point gave a measurement
  std::int64_t points = 0;           // points of mapped scans
  std::int64_t measurements = 0;     // cell measurements folded in
  std::int64_t poses_accepted = 0;
  std::int64_t poses_rejected = 0;   // out of order, duplicate time, NaN, not a unit quaternion
};

enum class ScanOutcome { kMapped, kUncovered, kEmpty };

class OfflineMapping {
 public:
  static Result<OfflineMapping> create(const pipeline::MapperConfig& config);

  // Moves every moving-sensor scan by a pose correction (scan matching or RBPF on a planar cut of the
  // scan) before it is measured; the corrected body pose of each mapped scan is kept (correctedPoses()).
  void setPoseCorrection(correction::ScanPoseCorrection correction) { correction_.emplace(std::move(correction)); }
  // The corrected body pose at the middle of each mapped scan, in scan order (empty without a correction).
  const std::vector<fusion::Pose>& correctedPoses() const { return corrected_; }

  // Loads the whole odometry (in order); rejected poses are counted. Call once before addScan.
  void setOdometry(std::span<const fusion::Pose> poses);
  // The odometry's time span; nullopt when it holds fewer than one pose.
  std::optional<std::pair<std::int64_t, std::int64_t>> odometrySpan() const;

  // A moving sensor: every point placed with the body pose at its own time.
  ScanOutcome addScan(const ScanRecord& scan, TimeBase base);
  // The first scan the odometry left out that lies on another clock than the odometry (more than
  // ClockAgreement's tolerance from its nearest pose): its times, the offset and the fix (describe()).
  // nullopt while every scan left out lies near the odometry. Meaningful when no scan was covered: a
  // shorter odometry also leaves scans far from it.
  const std::optional<fusion::ClockAgreement>& clockMismatch() const { return clock_mismatch_; }
  // A sensor that does not move: the body at `odom_from_body`, the sensor at body · extrinsic.
  ScanOutcome addStaticScan(const ScanRecord& scan, const Eigen::Isometry3d& odom_from_body);
  // Rays from one origin to points given in the map frame (a PCD cloud with its viewpoint).
  ScanOutcome addCloud(const Eigen::Vector3d& origin, std::span<const Eigen::Vector3d> points);

  // Keeps the regions farther than `distance_m` from the sensor in page files in `dir` while mapping
  // (map_pager.hpp): the map is the same, bit for bit; memory holds only the regions near the sensor.
  Status setPaging(const std::filesystem::path& dir, double distance_m);
  // Brings every paged-out region back (before the whole map is saved or exported).
  Status bringInAll();
  // The paged-out part: its blocks' checksum term (for BandedOgf::checksum) and its cells; zero without paging.
  filter::BlockHashSum pagedBlocks() const { return pager_ ? pager_->heldBlocks() : filter::BlockHashSum{}; }
  const persistence::MapPager* pager() const { return pager_ ? &*pager_ : nullptr; }

  const OfflineCounts& counts() const { return counts_; }
  pipeline::ScanMapper& mapper() { return mapper_; }
  const pipeline::ScanMapper& mapper() const { return mapper_; }

 private:
  OfflineMapping(pipeline::ScanMapper mapper, const pipeline::MapperConfig& config);
  ScanOutcome fold(std::size_t points);

  pipeline::ScanMapper mapper_;
  pipeline::MapperConfig config_;
  std::optional<fusion::PoseBuffer> poses_;
  std::optional<correction::ScanPoseCorrection> correction_;
  std::vector<fusion::Pose> corrected_;
  ScanRecord cloud_;  // addCloud's points as a sensor-frame scan
  std::optional<persistence::MapPager> pager_;
  double page_out_distance_m_ = 0.0;
  Status paging_ = okStatus();  // the first paging failure; mapping stops paging then
  std::optional<fusion::ClockAgreement> clock_mismatch_;
  OfflineCounts counts_;
};

}  // namespace ogf::map_io
