// ogf-mapper's intake of scans, poses and keyframe requests (scan_intake.hpp): the Asio thread's side,
// which checks and queues, and the worker's, which takes the scans that are ready.
#include "ogf/mapper_daemon/scan_intake.hpp"

#include <spdlog/spdlog.h>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"

namespace ogf::mapper_daemon {

using adapters::decodePose;
using adapters::scanPointsOf;
using adapters::validateScan;

namespace {

// Seconds between two microsecond times, for the log.
double secondsBetween(std::int64_t later, std::int64_t earlier) { return static_cast<double>(later - earlier) * 1e-6; }

// Whether a message whose clock TimeSanity judged (before check() took it in) goes on; logs a refusal
// (rate-limited) with the times it was judged against, or a followed jump.
bool timePlausible(const char* what, fusion::TimeVerdict verdict, const fusion::TimeSanity& clock,
                   std::optional<std::int64_t> expected, std::int64_t utime, std::int64_t wall_utime,
                   transport::LogRateLimiter& log) {
  using fusion::TimeVerdict;
  if (verdict == TimeVerdict::kAccept) return true;
  if (verdict == TimeVerdict::kFollowJump) {
    spdlog::warn("{} clock jumped from {} to {} (host clock {}): followed after consistent messages", what,
                 clock.timeBeforeLastJump() ? std::to_string(*clock.timeBeforeLastJump()) : "none", utime, wall_utime);
    return true;
  }
  const auto n = log.allow();
  if (!n) return false;
  const double max_ahead_s = static_cast<double>(clock.maxAheadUs()) * 1e-6;
  std::string why;
  if (verdict == TimeVerdict::kAheadOfHost) {
    why = fmt::format("{:.3f} s ahead of the host clock {} (at most {} s is plausible)", secondsBetween(utime, wall_utime),
                      wall_utime, max_ahead_s);
  } else if (verdict == TimeVerdict::kAheadOfStream && expected) {
    why = fmt::format("{:.3f} s ahead of the stream, which is expected at {} (its newest time {} plus the host time "
                      "since; at most {} s beyond is plausible)",
                      secondsBetween(utime, *expected), *expected, clock.reference().value_or(0), max_ahead_s);
  } else {
    why = fmt::format("{:.3f} s behind the stream's newest time {} (at most {} s is plausible)",
                      secondsBetween(clock.reference().value_or(utime), utime), clock.reference().value_or(0),
                      static_cast<double>(clock.maxBehindUs()) * 1e-6);
  }
  spdlog::warn("{} at {} refused: {}; host clock {} ({} more)", what, utime, why, wall_utime, *n);
  return false;
}

}  // namespace

ScanIntake::ScanIntake(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared)
    : options_(options),
      lcm_(lcm),
      shared_(shared),
      poses_(options.map.fusion.pose_buffer),
      pending_(options.map.fusion.pending),
      pose_clock_(options.map.fusion.time_sanity),
      scan_clock_(options.map.fusion.time_sanity),
      inputs_(inputWatchConfig(), steadyUtime()) {}

void ScanIntake::subscribe() {
  scan_sub_ = std::make_unique<transport::Subscriber<ogf::lidar_scan_t>>(
      lcm_, options_.scan_channel,
      [this](const ogf::lidar_scan_t& s, const lcm::ReceiveBuffer&, const std::string&) { onScan(s); },
      [this](const std::string& ch, std::size_t size, std::string_view why) { onMalformedScan(ch, size, why); });
  request_sub_ = std::make_unique<transport::Subscriber<ogf::map_request_t>>(
      lcm_, options_.request_channel,
      [this](const ogf::map_request_t& r, const lcm::ReceiveBuffer&, const std::string&) { onRequest(r); },
      [this](const std::string& ch, std::size_t size, std::string_view why) { onMalformedRequest(ch, size, why); });
}

void ScanIntake::subscribePoses() {
  pose_sub_ = lcm_.subscribeFunction(
      options_.pose_channel,
      +[](const lcm::ReceiveBuffer* rb, const std::string&, ScanIntake* self) { self->onPose(*rb); }, this);
  if (pose_sub_ != nullptr) pose_sub_->setQueueCapacity(transport::kSubscriptionQueueCapacity);
}

void ScanIntake::unsubscribe() {
  if (pose_sub_ != nullptr) lcm_.unsubscribe(pose_sub_);
  pose_sub_ = nullptr;
  scan_sub_.reset();
  request_sub_.reset();
}

void ScanIntake::restartInputWatch() { inputs_ = fusion::InputWatch(inputWatchConfig(), steadyUtime()); }

std::optional<ScanIntake::Pending::Entry> ScanIntake::nextScan(std::int64_t now) {
  return staticPose() ? pending_.popOldest() : pending_.popReady(poses_, now);
}

bool ScanIntake::takeKeyframeRequest() {
  const bool requested = keyframe_requested_;
  keyframe_requested_ = false;
  return requested;
}

void ScanIntake::fillStatus(ogf::mapper_status_t& s) const {
  const auto& pc = pending_.counts();
  s.scans_in = pc.scans_in + malformed_scans_;
  s.scans_dropped_behind = pc.scans_dropped_behind;
  s.scans_dropped_no_pose = pc.scans_dropped_no_pose;
  s.scans_late = pc.scans_late;
  s.scans_rejected = pc.scans_rejected + malformed_scans_;
  s.poses_in = poses_.counts().accepted + poses_.counts().rejected() + malformed_poses_;
  s.poses_rejected = poses_.counts().rejected() + malformed_poses_;
  s.requests_in = requests_ + malformed_requests_;
  s.requests_rejected = malformed_requests_;
  s.scans_refused_time = scan_clock_.counts().refused();
  s.poses_refused_time = pose_clock_.counts().refused();
  s.clock_jumps = scan_clock_.counts().jumps_followed + pose_clock_.counts().jumps_followed;
  s.pose_jumps = poses_.counts().jumps;
  s.scans_dropped_pose_jump = pc.scans_dropped_pose_jump;
  s.scans_in += s.scans_refused_time;
  s.poses_in += s.poses_refused_time;
  fillClockStatus(s);
  fillInputStatus(s);
}

void ScanIntake::onMalformedScan(const std::string& channel, std::size_t size, std::string_view why) {
  {
    std::lock_guard lk(shared_.mu);
    ++malformed_scans_;
    inputs_.scanArrived(steadyUtime());
  }
  if (auto n = bad_scan_log_.allow()) spdlog::warn("scan on {} ({} bytes) {} ({} more)", channel, size, why, *n);
}

void ScanIntake::onScan(const ogf::lidar_scan_t& scan) {
  if (auto st = validateScan(scan); !st) {
    {
      std::lock_guard lk(shared_.mu);
      ++malformed_scans_;
      inputs_.scanArrived(steadyUtime());
    }
    if (auto n = bad_scan_log_.allow()) spdlog::warn("scan seq {} rejected: {} ({} more)", scan.seq, st.error().message, *n);
    return;
  }
  auto owned = std::make_shared<const ogf::lidar_scan_t>(scan);
  const fusion::ScanTimeSpan span = fusion::timeSpanOf(scanPointsOf(*owned, options_.time_base));
  std::lock_guard lk(shared_.mu);
  const std::int64_t wall = wallUtime(), steady = steadyUtime();
  inputs_.scanArrived(steady);
  watchClocks(scan);  // before the time checks: a scan on another clock than the odometry is told apart
  const auto expected = scan_clock_.expectedAt(steady);
  const auto verdict = scan_clock_.check(span.end_utime, wall, steady);
  if (!timePlausible("scan", verdict, scan_clock_, expected, span.end_utime, wall, bad_time_log_)) return;
  if (verdict == fusion::TimeVerdict::kFollowJump) pending_.restartClock();
  const auto outcome = pending_.push({span.begin_utime, span.end_utime, static_cast<std::size_t>(scan.num_points)},
                                     std::move(owned), poses_, steady);
  if (outcome == fusion::PushOutcome::kLate) {
    if (auto n = bad_scan_log_.allow()) spdlog::warn("scan seq {} arrived after a newer one: dropped ({} more)", scan.seq, *n);
  }
  shared_.wake();
}

void ScanIntake::onRequest(const ogf::map_request_t& r) {
  spdlog::debug("keyframe requested by {} (last seq {})", r.requester, r.last_seq);
  std::lock_guard lk(shared_.mu);
  ++requests_;
  keyframe_requested_ = true;
  shared_.wake();
}

void ScanIntake::onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why) {
  {
    std::lock_guard lk(shared_.mu);
    ++malformed_requests_;
  }
  if (auto n = bad_request_log_.allow()) {
    spdlog::warn("map request on {} ({} bytes) {} ({} more)", channel, size, why, *n);
  }
}

void ScanIntake::onPose(const lcm::ReceiveBuffer& rb) {
  if (staticPose()) {
    std::lock_guard lk(shared_.mu);
    inputs_.poseArrived(steadyUtime());
    poseIgnored();
    return;
  }
  auto pose = decodePose(rb.data, rb.data_size);
  if (!pose) {
    {
      std::lock_guard lk(shared_.mu);
      ++malformed_poses_;
      inputs_.poseArrived(steadyUtime());
    }
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("message on {} ({} bytes): {} ({} more)", options_.pose_channel, rb.data_size, pose.error().message, *n);
    return;
  }
  fusion::PoseInsertResult r;
  {
    std::lock_guard lk(shared_.mu);
    // A pose refused for its content is counted as such by insert(), whatever its time.
    const std::int64_t wall = wallUtime(), steady = steadyUtime();
    inputs_.poseArrived(steady);
    const auto expected = pose_clock_.expectedAt(steady);
    const auto verdict = poses_.contentRejection(*pose) == fusion::PoseRejection::kNone
                             ? pose_clock_.check(pose->utime, wall, steady)
                             : fusion::TimeVerdict::kAccept;
    if (!timePlausible("pose", verdict, pose_clock_, expected, pose->utime, wall, bad_time_log_)) return;
    if (verdict == fusion::TimeVerdict::kFollowJump) poses_.clear();
    r = poses_.insert(*pose);
    if (r.accepted()) last_pose_steady_ = steadyUtime();
    shared_.wake();
  }
  if (!r.accepted()) {
    static constexpr const char* kWhy[] = {"",         "out of order",          "at a duplicate time",
                                           "not finite", "not a unit quaternion", "absurdly far from the origin"};
    if (auto n = bad_pose_log_.allow())
      spdlog::warn("pose at {} rejected: {} ({} more)", pose->utime, kWhy[static_cast<int>(r.rejection)], *n);
  } else if (r.jump) {
    if (auto n = jump_log_.allow())
      spdlog::warn("odometry jumped {:.3f} m / {:.3f} rad at {}: beyond max_pose_jump, scans spanning it are dropped ({} more)",
                   r.step_translation_m, r.step_rotation_rad,
                   pose->utime, *n);
  }
}

}  // namespace ogf::mapper_daemon
