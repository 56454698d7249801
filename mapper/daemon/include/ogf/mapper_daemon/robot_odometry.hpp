// One robot's odometry in ogf-mapper: the poses on its pose channel, received on the Asio thread, checked
// (malformed messages, rejected poses, implausible times: counted and logged at a limited rate) and kept in
// the PoseBuffer its sources' scans are placed with. With pose_source static, what arrives is only counted.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/fusion/time_sanity.hpp>

#include <cstdint>
#include <functional>
#include <string>

#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/transport/logging.hpp"

namespace ogf::mapper_daemon {

// Its poses' counts, as mapper_status_t and source_status_t name them.
struct OdometryCounts {
  std::int64_t poses_in = 0;  // every message on the channel, malformed and refused ones included
  std::int64_t poses_rejected = 0;
  std::int64_t poses_refused_time = 0;
  std::int64_t clock_jumps = 0;
  std::int64_t pose_jumps = 0;
  std::int64_t poses_ignored = 0;  // while the pose is static

  // Sums the counts of several robots.
  OdometryCounts& operator+=(const OdometryCounts& o) {
    poses_in += o.poses_in;
    poses_rejected += o.poses_rejected;
    poses_refused_time += o.poses_refused_time;
    clock_jumps += o.clock_jumps;
    pose_jumps += o.pose_jumps;
    poses_ignored += o.poses_ignored;
    return *this;
  }
};

class RobotOdometry {
 public:
  // `label` prefixes its log lines ("" with one robot, "robot r1: " with several).
  RobotOdometry(std::string robot, std::string channel, std::string label, const MapperOptions& options,
                SharedState& shared);
  RobotOdometry(const RobotOdometry&) = delete;
  RobotOdometry& operator=(const RobotOdometry&) = delete;
  ~RobotOdometry();

  // `arrived` is told (shared.mu held) of every message on the channel, whatever becomes of it: the input
  // watch of each of the robot's sources.
  void subscribe(lcm::LCM& lcm, std::function<void(std::int64_t steady_utime)> arrived);
  void unsubscribe();

  const std::string& robot() const { return robot_; }
  const std::string& channel() const { return channel_; }
  // The rest with shared.mu held.
  const fusion::PoseBuffer& poses() const { return poses_; }
  // The newest pose's time while poses keep arriving (within `fresh_us` of `steady_now`), else nothing: only
  // odometry that is still arriving says which clock it is on.
  std::optional<std::int64_t> newestFreshPose(std::int64_t steady_now, std::int64_t fresh_us) const;
  OdometryCounts counts() const;

 private:
  void onPose(const lcm::ReceiveBuffer& rb);
  void ignored();  // a message while the pose is static: counted, said once
  void logRejection(const fusion::PoseInsertResult& r, std::int64_t utime);

  const std::string robot_, channel_, label_;
  const MapperOptions& options_;
  SharedState& shared_;
  lcm::LCM* lcm_ = nullptr;
  lcm::Subscription* sub_ = nullptr;
  std::function<void(std::int64_t)> arrived_;

  // Under shared_.mu:
  fusion::PoseBuffer poses_;
  fusion::TimeSanity clock_;
  std::int64_t malformed_ = 0;
  std::int64_t ignored_ = 0;
  std::int64_t last_pose_steady_ = 0;  // when the last pose was accepted (0: never)

  transport::LogRateLimiter bad_pose_log_, jump_log_, bad_time_log_;
};

}  // namespace ogf::mapper_daemon
