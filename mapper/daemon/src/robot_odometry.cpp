// One robot's odometry (robot_odometry.hpp).
#include "ogf/mapper_daemon/robot_odometry.hpp"

#include <spdlog/spdlog.h>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/transport/subscriber.hpp"
#include "time_refusal.hpp"

namespace ogf::mapper_daemon {

RobotOdometry::RobotOdometry(std::string robot, std::string channel, std::string label, const MapperOptions& options,
                             SharedState& shared)
    : robot_(std::move(robot)),
      channel_(std::move(channel)),
      label_(std::move(label)),
      options_(options),
      shared_(shared),
      poses_(options.map.fusion.pose_buffer),
      clock_(options.map.fusion.time_sanity) {}

RobotOdometry::~RobotOdometry() { unsubscribe(); }

void RobotOdometry::subscribe(lcm::LCM& lcm, std::function<void(std::int64_t)> arrived) {
  lcm_ = &lcm;
  arrived_ = std::move(arrived);
  sub_ = lcm.subscribeFunction(
      channel_, +[](const lcm::ReceiveBuffer* rb, const std::string&, RobotOdometry* self) { self->onPose(*rb); }, this);
  if (sub_ != nullptr) sub_->setQueueCapacity(transport::kSubscriptionQueueCapacity);
}

void RobotOdometry::unsubscribe() {
  if (lcm_ != nullptr && sub_ != nullptr) lcm_->unsubscribe(sub_);
  sub_ = nullptr;
}

std::optional<std::int64_t> RobotOdometry::newestFreshPose(std::int64_t steady_now, std::int64_t fresh_us) const {
  if (poses_.empty() || last_pose_steady_ == 0 || steady_now - last_pose_steady_ > fresh_us) return std::nullopt;
  return poses_.newest().utime;
}

OdometryCounts RobotOdometry::counts() const {
  OdometryCounts c;
  c.poses_rejected = poses_.counts().rejected() + malformed_;
  c.poses_refused_time = clock_.counts().refused();
  c.poses_in = poses_.counts().accepted + c.poses_rejected + c.poses_refused_time;
  c.clock_jumps = clock_.counts().jumps_followed;
  c.pose_jumps = poses_.counts().jumps;
  c.poses_ignored = ignored_;
  return c;
}

void RobotOdometry::ignored() {
  if (++ignored_ == 1)
    spdlog::warn(
        "{}inputs: messages arrive on {} but the pose is static (pose_source: static): they are ignored and "
        "counted (poses_ignored); every scan is mapped at static_pose",
        label_, channel_);
}

void RobotOdometry::onPose(const lcm::ReceiveBuffer& rb) {
  if (options_.pose_source == PoseSource::kStatic) {
    std::lock_guard lk(shared_.mu);
    arrived_(steadyUtime());
    ignored();
    return;
  }
  auto pose = adapters::decodePose(rb.data, rb.data_size);
  if (!pose) {
    {
      std::lock_guard lk(shared_.mu);
      ++malformed_;
      arrived_(steadyUtime());
    }
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("{}message on {} ({} bytes): {} ({} more)", label_, channel_, rb.data_size, pose.error().message, *n);
    return;
  }
  fusion::PoseInsertResult r;
  {
    std::lock_guard lk(shared_.mu);
    // A pose refused for its content is counted as such by insert(), whatever its time.
    const std::int64_t wall = wallUtime(), steady = steadyUtime();
    arrived_(steady);
    const auto expected = clock_.expectedAt(steady);
    const auto verdict = poses_.contentRejection(*pose) == fusion::PoseRejection::kNone
                             ? clock_.check(pose->utime, wall, steady)
                             : fusion::TimeVerdict::kAccept;
    if (!timePlausible(label_ + "pose", verdict, clock_, expected, pose->utime, wall, bad_time_log_)) return;
    if (verdict == fusion::TimeVerdict::kFollowJump) poses_.clear();
    r = poses_.insert(*pose);
    if (r.accepted()) last_pose_steady_ = steadyUtime();
    shared_.wake();
  }
  logRejection(r, pose->utime);
}

void RobotOdometry::logRejection(const fusion::PoseInsertResult& r, std::int64_t utime) {
  if (!r.accepted()) {
    static constexpr const char* kWhy[] = {"",         "out of order",          "at a duplicate time",
                                           "not finite", "not a unit quaternion", "absurdly far from the origin"};
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("{}pose at {} rejected: {} ({} more)", label_, utime, kWhy[static_cast<int>(r.rejection)], *n);
  } else if (r.jump) {
    if (auto n = jump_log_.allow())
      spdlog::warn("{}odometry jumped {:.3f} m / {:.3f} rad at {}: beyond max_pose_jump, scans spanning it are dropped "
                   "({} more)",
                   label_, r.step_translation_m, r.step_rotation_rad, utime, *n);
  }
}

}  // namespace ogf::mapper_daemon
