#include "ogf/slam2d/run_outputs.hpp"

#include <algorithm>
#include <fstream>

namespace ogf::slam2d {

Status writeResultLog(const std::string& path, const SlamLog& log,
                      const std::vector<slam::Pose2>& corrected) {
  std::ofstream out(path);
  for (std::size_t i = 0; i < log.lasers.size(); ++i)
    slam_io::writeResultRecord(out, log.lasers[i], toLogPose(corrected[i]));
  out.flush();
  if (!out) return Error{"cannot write " + path};
  return okStatus();
}

std::vector<slam_io::StampedPose> stampedTrajectory(const SlamLog& log,
                                                    const std::vector<slam::Pose2>& corrected) {
  std::vector<slam_io::StampedPose> trajectory;
  trajectory.reserve(log.lasers.size());
  for (std::size_t i = 0; i < log.lasers.size(); ++i)
    trajectory.push_back({log.lasers[i].stamp.ipc_timestamp, toLogPose(corrected[i])});
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const auto& a, const auto& b) { return a.t < b.t; });
  return trajectory;
}

}  // namespace ogf::slam2d
