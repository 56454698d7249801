// The per-scan pose-correction front end over GridFastSlam.
#include "ogf/slam/pose_corrector.hpp"

#include <string>

namespace ogf::slam {

Result<CorrectionMode> parseCorrectionMode(std::string_view text) {
  if (text == "none") return CorrectionMode::kNone;
  if (text == "scan-match") return CorrectionMode::kScanMatch;
  if (text == "rbpf") return CorrectionMode::kRbpf;
  return Error::configuration("unknown pose-correction mode '" + std::string(text) + "' (none, scan-match, rbpf)");
}

std::string_view toString(CorrectionMode mode) {
  switch (mode) {
    case CorrectionMode::kNone:
      return "none";
    case CorrectionMode::kScanMatch:
      return "scan-match";
    case CorrectionMode::kRbpf:
      return "rbpf";
  }
  return "?";
}

namespace {
GridFastSlamConfig effectiveSlamConfig(const PoseCorrectorConfig& config) {
  GridFastSlamConfig c = config.slam;
  if (config.mode == CorrectionMode::kScanMatch) {
    const GridFastSlamConfig preset = GridFastSlamConfig::scanMatching();
    c.particles = preset.particles;
    c.sample_proposal = preset.sample_proposal;
    c.two_step_sampling = preset.two_step_sampling;
  }
  return c;
}
}  // namespace

Status PoseCorrectorConfig::validate() const {
  if (mode == CorrectionMode::kNone) return okStatus();
  return effectiveSlamConfig(*this).validate();
}

Result<PoseCorrector> PoseCorrector::create(const PoseCorrectorConfig& config) {
  PoseCorrector pc;
  if (config.mode == CorrectionMode::kNone) return pc;
  auto slam = GridFastSlam::create(effectiveSlamConfig(config));
  if (!slam) return slam.error();
  pc.slam_.emplace(std::move(*slam));
  return pc;
}

Pose2 PoseCorrector::correct(const Pose2& odometry, const PlanarScan& scan) {
  const std::uint64_t id = next_scan_id_++;
  if (!slam_) return odometry;
  slam_->addScan(id, odometry, scan);
  return slam_->currentPose(odometry);
}

std::vector<Pose2> PoseCorrector::correctedTrajectory(const std::vector<Pose2>& odometry) const {
  if (!slam_ || slam_->statistics().scans_processed == 0) return odometry;
  const std::vector<TrajectoryPoint> points = slam_->bestTrajectory();
  std::vector<Pose2> out(odometry.size());
  for (std::size_t i = 0; i < odometry.size(); ++i) out[i] = slam_->poseWithHindsight(points, i, odometry[i]);
  return out;
}

}  // namespace ogf::slam
