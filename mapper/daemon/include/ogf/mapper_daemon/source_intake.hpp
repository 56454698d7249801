// One source of ogf-mapper's scans (a lidar on a robot, source_options.hpp): its scans, received on the Asio
// thread (decoded here first when the source sends raw packets), checked (malformed messages, implausible
// times: counted and logged at a limited rate) and held until the worker maps them: a scan waits in
// PendingScans until its robot's odometry covers it (with pose_source static, every scan is ready at once).
// Its own watch over its inputs (source_inputs.cpp) and its clock against its robot's odometry
// (source_clocks.cpp) say when an input stops or the clocks disagree. Nothing one source receives stops
// another: each has its own queue, clocks and counters.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/fusion/clock_agreement.hpp>
#include <ogf/fusion/input_watch.hpp>
#include <ogf/fusion/pending_scans.hpp>
#include <ogf/fusion/time_sanity.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/source_status_t.hpp>
#include <ogf/velodyne/packet_stream.hpp>
#include <ogf/velodyne_packets_t.hpp>

#include <Eigen/Core>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/robot_odometry.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/mapper_daemon/source_options.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace ogf::mapper_daemon {

// The decoder of a source that sends raw packets (its calibration loaded); nothing for a source of scans.
// Fails naming the source and the calibration file.
Result<std::optional<velodyne::PacketStream>> packetStreamFor(const ResolvedSource& source);

// An input state as mapper_status_t's INPUTS_* constant.
std::int8_t inputsCode(fusion::InputState state);

class SourceIntake {
 public:
  using ScanPtr = std::shared_ptr<const ogf::lidar_scan_t>;
  using Pending = fusion::PendingScans<ScanPtr>;

  // `label` prefixes its log lines ("" with one source, "source front: " with several).
  // `io` runs the LCM handlers (the Asio thread): a raw packet source's idle timer runs there too.
  SourceIntake(ResolvedSource source, std::string label, std::optional<velodyne::PacketStream> packets,
               const MapperOptions& options, RobotOdometry& robot, SharedState& shared, boost::asio::io_context& io);
  SourceIntake(const SourceIntake&) = delete;
  SourceIntake& operator=(const SourceIntake&) = delete;

  void subscribe(lcm::LCM& lcm);
  void unsubscribe();

  const ResolvedSource& source() const { return source_; }
  // The rest with shared.mu held.
  const fusion::PoseBuffer& poses() const { return robot_.poses(); }
  // The oldest scan when it is ready to map (its poses have arrived; any, with a static pose), else nothing;
  // scans that waited too long expire on the way. popFront() takes it.
  const Pending::Entry* readyFront(std::int64_t now);
  Pending::Entry popFront() { return pending_.popFront(); }
  // The worker mapped one of its scans: `measurements` cells, the sensor at `sensor_origin` (map frame).
  // The status shows it from the next reportMapped(), together with the map's figures of the same scan.
  void scanMapped(std::int64_t measurements, const Eigen::Vector3d& sensor_origin);
  // The scans mapped so far, their measurements and the trail go into the status from now on.
  void reportMapped() { reported_ = mapped_; }
  // The scans mapped and their measurements as the status shows them (at the last reportMapped()).
  std::int64_t scansReported() const { return reported_.scans; }
  std::int64_t measurementsReported() const { return reported_.measurements; }
  // Its robot's odometry arrived (a message, whatever became of it).
  void poseArrived(std::int64_t steady_utime) { inputs_.poseArrived(steady_utime); }
  // The inputs' silence counts from here.
  void restartInputWatch(std::int64_t steady_utime);
  // Re-evaluates which inputs arrive and logs a change of state once (source_inputs.cpp).
  void watchInputs(std::int64_t steady_utime);
  fusion::InputState inputState() const { return inputs_.state(); }
  const fusion::PendingScansCounts& pendingCounts() const { return pending_.counts(); }
  // Scans received, malformed ones included.
  std::int64_t scansIn() const { return pending_.counts().scans_in + malformed_scans_ + throttled_scans_; }
  std::int64_t throttledScans() const { return throttled_scans_; }
  std::int64_t malformedScans() const { return malformed_scans_; }
  std::int64_t scansRefusedTime() const { return clock_.counts().refused(); }
  std::int64_t clockJumps() const { return clock_.counts().jumps_followed; }
  ogf::source_status_t status(std::int64_t steady_now) const;
  // The clock state of its last scan (source_clocks.cpp), as mapper_status_t and source_status_t name it.
  void fillClocks(std::int8_t& clocks, std::int8_t& scan_clock, std::int64_t& offset_us) const;

 private:
  void onScan(const ogf::lidar_scan_t& scan);
  // Whether the scan is larger than the model it names can send, counted and logged when it is.
  bool throttled(const ogf::lidar_scan_t& scan);
  void onMalformed(const std::string& channel, std::size_t size, std::string_view why);
  void onPackets(const ogf::velodyne_packets_t& batch);
  // A scan in progress goes out when no packets came for a few scan periods (the stream paused or ended),
  // as ogf-driver does, rather than waiting for the packets that would close it.
  void armIdleTimer();
  void watchClocks(const ogf::lidar_scan_t& scan);  // mu held
  bool staticPose() const { return options_.pose_source == PoseSource::kStatic; }
  // A missing input is said after 3 s: several scan periods (10 Hz) and far beyond odometry's (50-100 Hz).
  fusion::InputWatchConfig inputWatchConfig() const { return {3.0, !staticPose()}; }

  const ResolvedSource source_;
  const std::string label_;
  const MapperOptions& options_;
  RobotOdometry& robot_;
  SharedState& shared_;

  // Under shared_.mu:
  Pending pending_;
  fusion::TimeSanity clock_;
  fusion::ClockAgreement clocks_;
  fusion::InputWatch inputs_;
  bool inputs_were_ok_ = false;  // the inputs have been OK before (a return to OK is said as such)
  std::int64_t malformed_scans_ = 0;
  std::int64_t throttled_scans_ = 0;
  std::int64_t packets_in_ = 0;
  std::int64_t packets_rejected_ = 0;
  // What the worker has mapped of this source, and what of it the status shows (reportMapped).
  struct Mapped {
    std::int64_t scans = 0;
    std::int64_t measurements = 0;
    std::deque<Eigen::Vector3f> trail;  // the sensor's positions, newest last
  };
  Mapped mapped_;
  Mapped reported_;

  // The Asio thread's alone: the decoder of raw packets and the scan it fills.
  std::optional<velodyne::PacketStream> packets_;
  ogf::lidar_scan_t decoded_;
  boost::asio::steady_timer idle_timer_;
  bool idle_timer_armed_ = false;
  std::chrono::steady_clock::time_point last_batch_;

  std::unique_ptr<transport::Subscriber<ogf::lidar_scan_t>> scan_sub_;
  std::unique_ptr<transport::Subscriber<ogf::velodyne_packets_t>> packet_sub_;
  transport::LogRateLimiter bad_scan_log_, bad_time_log_;
  transport::LogRateLimiter throttle_log_{std::chrono::seconds(10)};
  transport::LogRateLimiter behind_log_{std::chrono::seconds(10)};  // a mapper behind stays behind a while
};

}  // namespace ogf::mapper_daemon
