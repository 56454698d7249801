// Driving the PoseCorrector over a log.
#include "ogf/slam2d/slam_run.hpp"

namespace ogf::slam2d {

Result<SlamRunResult> runSlam(const SlamLog& log, OdometrySource odometry,
                              const slam::PoseCorrectorConfig& config,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
  auto corrector = slam::PoseCorrector::create(config);
  if (!corrector) return corrector.error();
  SlamRunResult out;
  out.odometry = odometryAtLaserStamps(log, odometry);
  out.reversed_steps_repaired = repairReversedOdometry(log, out.odometry);
  const slam::Pose2 offset = laserOffset(log);
  for (std::size_t i = 0; i < log.lasers.size(); ++i) {
    (void)corrector->correct(out.odometry[i], toPlanarScan(log.lasers[i], offset));
    if (progress) progress(i + 1, log.lasers.size());
  }
  out.corrected = corrector->correctedTrajectory(out.odometry);
  if (const slam::GridFastSlam* s = corrector->slam()) {
    out.statistics = s->statistics();
    out.map = s->bestMap();
  }
  return out;
}

}  // namespace ogf::slam2d
