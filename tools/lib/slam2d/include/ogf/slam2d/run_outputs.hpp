// What an ogf-slam2d run leaves per laser record: the benchmark's result log (every laser record with its
// corrected pose in both pose triples and its original ipc_timestamp) and the corrected trajectory the
// relations metric scores (Kümmerle et al. 2009), sorted by time.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/slam/pose2.hpp>
#include <ogf/slam_io/relations.hpp>
#include <string>
#include <vector>

#include "ogf/slam2d/slam_log.hpp"

namespace ogf::slam2d {

// Writes the result log to `path`; `corrected` holds one pose per laser record. Error: "cannot write <path>".
Status writeResultLog(const std::string& path, const SlamLog& log, const std::vector<slam::Pose2>& corrected);

// Each laser record's stamp with its corrected pose, in time order: laser stamps are not monotonic in every
// log (intel: 631 steps back) and the metric wants them sorted; records with equal stamps keep log order.
std::vector<slam_io::StampedPose> stampedTrajectory(const SlamLog& log,
                                                    const std::vector<slam::Pose2>& corrected);

}  // namespace ogf::slam2d
