// ogf-mapper's watch over its inputs: whether scans arrive on the scan channel and poses on the pose
// channel (ogf::fusion::InputWatch), a warning naming the missing input, its channel and what to check
// when one stops (once per change, and a note when it comes back), and the state in OGF_MAPPER_STATUS.
// With pose_source static, what arrives on the pose channel is counted and said once, never used.
#include <spdlog/spdlog.h>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/scan_intake.hpp"
#include "ogf/transport/lcm_url.hpp"

namespace ogf::mapper_daemon {
namespace {

double seconds(std::int64_t us) { return static_cast<double>(us) * 1e-6; }

}  // namespace

void ScanIntake::watchInputs() {
  const std::int64_t now = steadyUtime();
  const auto change = inputs_.observe(now);
  if (!change) return;
  const std::string& scan = options_.scan_channel;
  const std::string& pose = options_.pose_channel;
  const std::string bus =
      transport::withReceiveBuffer(transport::resolveLcmUrl(options_.lcm_url));  // as main() joins it
  const auto silence = [&](std::optional<std::int64_t> since) {
    return since ? fmt::format("for {:.1f} s", seconds(*since))
                 : fmt::format("since the start {:.1f} s ago", seconds(inputs_.silentFor(now)));
  };
  using fusion::InputState;
  switch (change->state) {
    case InputState::kWaitingForPoses:
      spdlog::warn(
          "inputs: scans arrive on {} but no pose on {} {}: each scan waits max_pose_wait_s ({} s) for the "
          "poses covering it, then is dropped ({} so far, scans_dropped_no_pose). Check that the odometry "
          "runs and publishes ogf.odometry_t or bot_core.pose_t on {} (channels.pose, --pose-channel) on "
          "this LCM bus ({}); a sensor that does not move needs no odometry: pose_source: static (--static)",
          scan, pose, silence(inputs_.sincePose(now)), options_.map.fusion.pending.max_pose_wait_s,
          pending_.counts().scans_dropped_no_pose, pose, bus);
      break;
    case InputState::kWaitingForScans:
      if (staticPose()) {
        spdlog::warn(
            "inputs: no scan on {} {} (the pose is static: scans are all mapping needs). Check that "
            "ogf-driver runs and publishes on {} (channels.scan, --scan-channel) on this LCM bus ({})",
            scan, silence(inputs_.sinceScan(now)), scan, bus);
      } else {
        spdlog::warn(
            "inputs: poses arrive on {} but no scan on {} {}: nothing is mapped. Check that ogf-driver runs "
            "and publishes on {} (channels.scan, --scan-channel) on this LCM bus ({}); a log of the raw "
            "packets alone (VELODYNE_PACKETS) holds no scans",
            pose, scan, silence(inputs_.sinceScan(now)), scan, bus);
      }
      break;
    case InputState::kNone: {
      const std::string what = staticPose() ? "on " + scan : "on " + scan + " or " + pose;
      if (change->previous == InputState::kNone) {
        spdlog::warn(
            "inputs: nothing arrived {} in the {:.1f} s since the start: check that {} on this LCM "
            "bus ({}) and on these channels",
            what, seconds(inputs_.silentFor(now)),
            staticPose() ? "ogf-driver publishes" : "ogf-driver and the odometry publish", bus);
      } else {
        spdlog::warn("inputs: nothing {} for {:.1f} s: stopped, or no longer on this LCM bus ({})", what,
                     seconds(inputs_.silentFor(now)), bus);
      }
      break;
    }
    case InputState::kOk: {
      const bool again = inputs_were_ok_;
      inputs_were_ok_ = true;
      if (staticPose()) {
        spdlog::info("inputs: scans arrive on {}{}: mapping them at the static pose", scan,
                     again ? " again" : "");
      } else if (change->previous == InputState::kWaitingForPoses) {
        spdlog::info("inputs: poses arrive on {} again: scans on {} are mapped", pose, scan);
      } else if (change->previous == InputState::kWaitingForScans) {
        spdlog::info("inputs: scans arrive on {} again: mapping with the poses on {}", scan, pose);
      } else {
        spdlog::info("inputs: scans on {} and poses on {} arrive{}: mapping", scan, pose,
                     again ? " again" : "");
      }
      break;
    }
  }
}

void ScanIntake::fillInputStatus(ogf::mapper_status_t& s) const {
  switch (inputs_.state()) {
    case fusion::InputState::kNone:
      s.inputs = ogf::mapper_status_t::INPUTS_NONE;
      break;
    case fusion::InputState::kOk:
      s.inputs = ogf::mapper_status_t::INPUTS_OK;
      break;
    case fusion::InputState::kWaitingForPoses:
      s.inputs = ogf::mapper_status_t::INPUTS_WAITING_FOR_POSES;
      break;
    case fusion::InputState::kWaitingForScans:
      s.inputs = ogf::mapper_status_t::INPUTS_WAITING_FOR_SCANS;
      break;
  }
  const std::int64_t now = steadyUtime();
  const auto age = [](std::optional<std::int64_t> us) {
    return us ? static_cast<float>(seconds(*us)) : -1.0f;
  };
  s.last_scan_age_s = age(inputs_.sinceScan(now));
  s.last_pose_age_s = age(inputs_.sincePose(now));
  s.pose_source =
      staticPose() ? ogf::mapper_status_t::POSE_SOURCE_STATIC : ogf::mapper_status_t::POSE_SOURCE_ODOMETRY;
  s.poses_ignored = poses_ignored_;
}

void ScanIntake::poseIgnored() {
  if (++poses_ignored_ == 1)
    spdlog::warn(
        "inputs: messages arrive on {} but the pose is static (pose_source: static): they are ignored and "
        "counted (poses_ignored); every scan is mapped at static_pose",
        options_.pose_channel);
}

}  // namespace ogf::mapper_daemon
