#include "ogf/correction/scan_pose_correction.hpp"

#include <cmath>

#include "ogf/correction/planar_pose.hpp"

namespace ogf::correction {

Status ScanPoseCorrectionConfig::validate() const {
  if (auto st = corrector.validate(); !st) return Error::configuration("corrector." + st.error().message);
  if (corrector.mode == slam::CorrectionMode::kNone) return okStatus();
  if (auto st = projection.validate(); !st) return Error::configuration("projection." + st.error().message);
  return okStatus();
}

Result<ScanPoseCorrection> ScanPoseCorrection::create(const ScanPoseCorrectionConfig& config) {
  if (auto st = config.validate(); !st) return st.error();
  auto corrector = slam::PoseCorrector::create(config.corrector);
  if (!corrector) return Error::configuration("corrector." + corrector.error().message);
  return ScanPoseCorrection(config, std::move(*corrector));
}

ScanCorrection ScanPoseCorrection::correct(const Eigen::Isometry3d& odom_from_body,
                                           std::span<const Eigen::Vector3d> endpoints_odom) {
  ScanCorrection out;
  out.map_from_body = odom_from_body;
  if (mode_ == slam::CorrectionMode::kNone) return out;

  // The deskewed scan as the body saw it at the reference time.
  const Eigen::Isometry3d body_from_odom = odom_from_body.inverse();
  points_body_.clear();
  points_body_.reserve(endpoints_odom.size());
  for (const Eigen::Vector3d& p : endpoints_odom) points_body_.push_back((body_from_odom * p).cast<float>());
  const slam::PlanarScan planar = slam::projectToPlanarScan(points_body_, projection_);
  for (float r : planar.ranges_m)
    if (planar.isValid(r) && !planar.isNoReturn(r)) ++out.planar_beams_used;

  const slam::Pose2 corrected = corrector_.correct(planarPoseOf(odom_from_body), planar);
  out.map_from_odom = correctionBetween(odom_from_body, corrected);
  out.map_from_body = out.map_from_odom * odom_from_body;
  return out;
}

}  // namespace ogf::correction
