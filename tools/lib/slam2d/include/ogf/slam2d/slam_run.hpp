// One 2-D SLAM run over a log held in memory: every laser record through the PoseCorrector in log order,
// then the corrected pose of every record from the best particle's history.
#pragma once

#include <cstddef>
#include <functional>
#include <ogf/common/result.hpp>
#include <ogf/slam/pose_corrector.hpp>
#include <optional>
#include <vector>

#include "ogf/slam2d/slam_log.hpp"

namespace ogf::slam2d {

struct SlamRunResult {
  std::vector<slam::Pose2> odometry;  // per laser record, after repairReversedOdometry
  std::size_t reversed_steps_repaired = 0;
  std::vector<slam::Pose2> corrected;  // per laser record, with hindsight
  slam::GridFastSlamStatistics statistics;
  std::optional<slam::TiledGrid> map;  // the best particle's (absent in mode none)
};

// `progress(done, total)` is called after every record.
Result<SlamRunResult> runSlam(const SlamLog& log, OdometrySource odometry,
                              const slam::PoseCorrectorConfig& config,
                              const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace ogf::slam2d
