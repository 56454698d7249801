// Pose correction for 3-D scans: the stage between the robot's odometry and the OGF. Each placed
// (deskewed) scan is cut to a planar scan in the body frame at the scan's reference time
// (slam/planar_projection.hpp), the PoseCorrector (none, scan-match or rbpf, slam/pose_corrector.hpp)
// estimates the corrected planar pose, and the result is a transform map_from_odom that moves the whole
// scan there. Height, roll and pitch stay as odometry measured them: a planar SLAM cannot observe them.
#pragma once

#include <Eigen/Geometry>

#include <span>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam/planar_projection.hpp"
#include "ogf/slam/pose_corrector.hpp"

namespace ogf::correction {

struct ScanPoseCorrectionConfig {
  slam::PoseCorrectorConfig corrector;      // mode none passes odometry through
  slam::PlanarProjectionConfig projection;  // the height band and bins of the planar scan

  ScanPoseCorrectionConfig() { corrector.mode = slam::CorrectionMode::kNone; }
  // The first wrong field ("corrector.slam.particles ...", "projection.z_max_m ...").
  Status validate() const;
};

struct ScanCorrection {
  Eigen::Isometry3d map_from_odom = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d map_from_body = Eigen::Isometry3d::Identity();  // the corrected body pose
  std::size_t planar_beams_used = 0;  // bins of the planar scan that held a point
};

class ScanPoseCorrection {
 public:
  static Result<ScanPoseCorrection> create(const ScanPoseCorrectionConfig& config);

  // `odom_from_body`: the odometry pose of the body at the scan's reference time; `endpoints_odom`: the
  // scan's points placed in the odometry frame (deskewed to that same odometry).
  ScanCorrection correct(const Eigen::Isometry3d& odom_from_body, std::span<const Eigen::Vector3d> endpoints_odom);

  slam::CorrectionMode mode() const { return mode_; }
  const slam::PoseCorrector& corrector() const { return corrector_; }
  std::uint64_t scansCorrected() const { return corrector_.scansSeen(); }

 private:
  ScanPoseCorrection(const ScanPoseCorrectionConfig& config, slam::PoseCorrector corrector)
      : mode_(config.corrector.mode), projection_(config.projection), corrector_(std::move(corrector)) {}

  slam::CorrectionMode mode_;
  slam::PlanarProjectionConfig projection_;
  slam::PoseCorrector corrector_;
  std::vector<Eigen::Vector3f> points_body_;
};

}  // namespace ogf::correction
