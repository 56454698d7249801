// One source's watch over its inputs: whether its scans arrive on its channel and its robot's poses on the
// pose channel (ogf::fusion::InputWatch), a warning naming the missing input, its channel and what to check
// when one stops (once per change, and a note when it comes back), and the state in OGF_MAPPER_STATUS.
#include <ogf/mapper_status_t.hpp>
#include <spdlog/spdlog.h>

#include "ogf/mapper_daemon/source_intake.hpp"
#include "ogf/transport/lcm_url.hpp"

namespace ogf::mapper_daemon {
namespace {

double seconds(std::int64_t us) { return static_cast<double>(us) * 1e-6; }

}  // namespace

std::int8_t inputsCode(fusion::InputState state) {
  switch (state) {
    case fusion::InputState::kNone: return ogf::mapper_status_t::INPUTS_NONE;
    case fusion::InputState::kOk: return ogf::mapper_status_t::INPUTS_OK;
    case fusion::InputState::kWaitingForPoses: return ogf::mapper_status_t::INPUTS_WAITING_FOR_POSES;
    case fusion::InputState::kWaitingForScans: return ogf::mapper_status_t::INPUTS_WAITING_FOR_SCANS;
  }
  return ogf::mapper_status_t::INPUTS_NONE;
}

void SourceIntake::watchInputs(std::int64_t now) {
  const auto change = inputs_.observe(now);
  if (!change) return;
  const std::string& scan = source_.channel;
  const std::string& pose = robot_.channel();
  const std::string bus =
      transport::withReceiveBuffer(transport::resolveLcmUrl(options_.lcm_url));  // as main() joins it
  const auto silence = [&](std::optional<std::int64_t> since) {
    return since ? fmt::format("for {:.1f} s", seconds(*since))
                 : fmt::format("since the start {:.1f} s ago", seconds(inputs_.silentFor(now)));
  };
  const std::string publishes = source_.packets ? "publishes raw packets (ogf.velodyne_packets_t) on " + scan
                                                : "publishes on " + scan + " (channels.scan, --scan-channel)";
  using fusion::InputState;
  switch (change->state) {
    case InputState::kWaitingForPoses:
      spdlog::warn(
          "{}inputs: scans arrive on {} but no pose on {} {}: each scan waits max_pose_wait_s ({} s) for the "
          "poses covering it, then is dropped ({} so far, scans_dropped_no_pose). Check that the odometry "
          "runs and publishes ogf.odometry_t or bot_core.pose_t on {} (channels.pose, --pose-channel) on "
          "this LCM bus ({}); a sensor that does not move needs no odometry: pose_source: static (--static)",
          label_, scan, pose, silence(inputs_.sincePose(now)), options_.map.fusion.pending.max_pose_wait_s,
          pending_.counts().scans_dropped_no_pose, pose, bus);
      break;
    case InputState::kWaitingForScans:
      if (staticPose()) {
        spdlog::warn(
            "{}inputs: no scan on {} {} (the pose is static: scans are all mapping needs). Check that "
            "ogf-driver runs and {} on this LCM bus ({})",
            label_, scan, silence(inputs_.sinceScan(now)), publishes, bus);
      } else {
        spdlog::warn(
            "{}inputs: poses arrive on {} but no scan on {} {}: nothing is mapped. Check that ogf-driver runs "
            "and {} on this LCM bus ({}){}",
            label_, pose, scan, silence(inputs_.sinceScan(now)), publishes, bus,
            source_.packets ? "" : "; a log of the raw packets alone (VELODYNE_PACKETS) holds no scans");
      }
      break;
    case InputState::kNone: {
      const std::string what = staticPose() ? "on " + scan : "on " + scan + " or " + pose;
      if (change->previous == InputState::kNone) {
        spdlog::warn(
            "{}inputs: nothing arrived {} in the {:.1f} s since the start: check that {} on this LCM "
            "bus ({}) and on these channels",
            label_, what, seconds(inputs_.silentFor(now)),
            staticPose() ? "ogf-driver publishes" : "ogf-driver and the odometry publish", bus);
      } else {
        // Both inputs stopping together is what an orderly stop looks like (a replay that ended, the robot
        // shutting down); one stopping alone is the fault, warned of above.
        spdlog::info("{}inputs: nothing {} for {:.1f} s: both stopped, or are no longer on this LCM bus ({})",
                     label_, what, seconds(inputs_.silentFor(now)), bus);
      }
      break;
    }
    case InputState::kOk: {
      const bool again = inputs_were_ok_;
      inputs_were_ok_ = true;
      if (staticPose()) {
        spdlog::info("{}inputs: scans arrive on {}{}: mapping them at the static pose", label_, scan,
                     again ? " again" : "");
      } else if (change->previous == InputState::kWaitingForPoses) {
        spdlog::info("{}inputs: poses arrive on {} again: scans on {} are mapped", label_, pose, scan);
      } else if (change->previous == InputState::kWaitingForScans) {
        spdlog::info("{}inputs: scans arrive on {} again: mapping with the poses on {}", label_, scan, pose);
      } else {
        spdlog::info("{}inputs: scans on {} and poses on {} arrive{}: mapping", label_, scan, pose,
                     again ? " again" : "");
      }
      break;
    }
  }
}

}  // namespace ogf::mapper_daemon
