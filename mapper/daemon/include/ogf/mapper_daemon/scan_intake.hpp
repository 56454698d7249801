// ogf-mapper's intake: scans on VELODYNE_SCAN, odometry on POSE and keyframe requests on OGF_MAP_REQUEST,
// received on the Asio thread, checked (malformed messages, implausible times, rejected poses: counted and
// logged at a limited rate) and held until the worker maps them: a scan waits in PendingScans until the
// odometry covers it (with pose_source static, every scan is ready at once and what arrives on POSE is
// only counted). The watch over the inputs (mapper_inputs.cpp) and over the two clocks
// (mapper_clocks.cpp) say when an input stops or the clocks disagree, and report both in the status.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/input_watch.hpp>
#include <ogf/fusion/pending_scans.hpp>
#include <ogf/fusion/pose_buffer.hpp>
#include <ogf/fusion/time_sanity.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <cstdint>
#include <memory>
#include <optional>

#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

class ScanIntake {
 public:
  using ScanPtr = std::shared_ptr<const ogf::lidar_scan_t>;
  using Pending = fusion::PendingScans<ScanPtr>;

  ScanIntake(const MapperOptions& options, lcm::LCM& lcm, SharedState& shared);
  ScanIntake(const ScanIntake&) = delete;
  ScanIntake& operator=(const ScanIntake&) = delete;

  // Subscribes the scan and request channels; subscribePoses() the pose channel.
  void subscribe();
  void subscribePoses();
  void unsubscribe();

  // The rest with shared.mu held.
  // The inputs' silence counts from here: from the start of mapping, not from before the map was
  // restored (a long journal replay).
  void restartInputWatch();
  // The next scan to map, oldest first: one whose poses have arrived (any, with a static pose); scans that
  // waited too long expire on the way.
  std::optional<Pending::Entry> nextScan(std::int64_t now);
  const fusion::PoseBuffer& poses() const { return poses_; }
  bool keyframeRequested() const { return keyframe_requested_; }
  // Whether a keyframe was requested since the last call.
  bool takeKeyframeRequest();
  // Re-evaluates which inputs arrive and logs a change of state once (mapper_inputs.cpp).
  void watchInputs();
  // The counts of scans, poses and requests, the clocks' and the inputs' state.
  void fillStatus(ogf::mapper_status_t& s) const;
  // Scans received, malformed ones included, and what became of them.
  std::int64_t scansIn() const { return pending_.counts().scans_in + malformed_scans_; }
  const fusion::PendingScansCounts& pendingCounts() const { return pending_.counts(); }

 private:
  void onScan(const ogf::lidar_scan_t& scan);
  void onMalformedScan(const std::string& channel, std::size_t size, std::string_view why);
  void onRequest(const ogf::map_request_t& request);
  void onMalformedRequest(const std::string& channel, std::size_t size, std::string_view why);
  void onPose(const lcm::ReceiveBuffer& rbuf);
  // Compares the scan with the newest pose (mu held); logs when the clocks start or stop agreeing.
  void watchClocks(const ogf::lidar_scan_t& scan);
  void fillClockStatus(ogf::mapper_status_t& s) const;
  void fillInputStatus(ogf::mapper_status_t& s) const;
  // A message arrived on the pose channel while the pose is static (mu held): counted, said once.
  void poseIgnored();
  bool staticPose() const { return options_.pose_source == PoseSource::kStatic; }
  // A missing input is said after 3 s: several scan periods (10 Hz) and far beyond odometry's (50-100 Hz).
  fusion::InputWatchConfig inputWatchConfig() const { return {3.0, !staticPose()}; }

  const MapperOptions& options_;
  lcm::LCM& lcm_;
  SharedState& shared_;

  // Under shared_.mu:
  fusion::PoseBuffer poses_;
  Pending pending_;
  fusion::TimeSanity pose_clock_, scan_clock_;
  bool keyframe_requested_ = false;
  std::int64_t malformed_scans_ = 0;
  fusion::ClockAgreement clocks_;
  fusion::InputWatch inputs_;
  bool inputs_were_ok_ = false;        // the inputs have been OK before (a return to OK is said as such)
  std::int64_t poses_ignored_ = 0;     // messages on the pose channel while the pose is static
  std::int64_t last_pose_steady_ = 0;  // when the last pose was accepted (0: never)
  std::int64_t malformed_poses_ = 0;
  std::int64_t requests_ = 0;            // well-formed keyframe requests
  std::int64_t malformed_requests_ = 0;  // refused by decodeMessage

  std::unique_ptr<transport::Subscriber<ogf::lidar_scan_t>> scan_sub_;
  std::unique_ptr<transport::Subscriber<ogf::map_request_t>> request_sub_;
  lcm::Subscription* pose_sub_ = nullptr;
  transport::LogRateLimiter bad_scan_log_, bad_pose_log_, bad_request_log_, jump_log_, bad_time_log_;
};

}  // namespace ogf::mapper_daemon
