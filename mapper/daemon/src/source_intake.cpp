// One source's intake (source_intake.hpp): the Asio thread's side, which decodes, checks and queues, and
// the worker's, which takes the scans that are ready and records where the sensor was.
#include "ogf/mapper_daemon/source_intake.hpp"

#include <ogf/mapper_status_t.hpp>

#include <spdlog/spdlog.h>

#include "ogf/adapters/message_adapters.hpp"
#include "ogf/driver_messages/scan_message.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/velodyne/model.hpp"
#include "ogf/velodyne/wire_format.hpp"
#include "time_refusal.hpp"

namespace ogf::mapper_daemon {
namespace {

// The sensor's trail in the status: positions at least this far apart, at most this many.
constexpr float kTrailSpacingM = 0.5f;
constexpr std::size_t kTrailPoints = 64;
// Scan periods without packets after which a raw packet source's scan in progress goes out (ogf-driver's
// rule: a burst of lost packets is not a pause).
constexpr double kIdleScanPeriods = 3.0;

}  // namespace

Result<std::optional<velodyne::PacketStream>> packetStreamFor(const ResolvedSource& source) {
  if (!source.packets) return std::optional<velodyne::PacketStream>();
  velodyne::StreamConfig config;
  if (!source.calibration.empty()) {
    auto calibration = velodyne::loadCalibrationFile(source.calibration);
    if (!calibration)
      return Error::configuration("sources (" + source.name + ").calibration: " + calibration.error().message);
    config.calibration = std::move(*calibration);
  }
  // The map's own range limits apply later (map.min_range, map.max_range); the decoder keeps every return.
  config.min_range_m = 0.0;
  auto stream = velodyne::PacketStream::create(config);
  if (!stream) return Error::configuration("sources (" + source.name + "): " + stream.error().message);
  return std::optional<velodyne::PacketStream>(std::move(*stream));
}

SourceIntake::SourceIntake(ResolvedSource source, std::string label, std::optional<velodyne::PacketStream> packets,
                           const MapperOptions& options, RobotOdometry& robot, SharedState& shared,
                           boost::asio::io_context& io)
    : source_(std::move(source)),
      label_(std::move(label)),
      options_(options),
      robot_(robot),
      shared_(shared),
      pending_(options.map.fusion.pending),
      clock_(options.map.fusion.time_sanity),
      inputs_(inputWatchConfig(), steadyUtime()),
      packets_(std::move(packets)),
      idle_timer_(io) {
  if (packets_) packets_->setScanSink([this](const velodyne::Scan& scan) {
      driver::fillScanMessage(scan, "velodyne", decoded_);
      onScan(decoded_);
    });
}

void SourceIntake::subscribe(lcm::LCM& lcm) {
  const auto malformed = [this](const std::string& ch, std::size_t size, std::string_view why) { onMalformed(ch, size, why); };
  if (packets_) {
    packet_sub_ = std::make_unique<transport::Subscriber<ogf::velodyne_packets_t>>(
        lcm, source_.channel,
        [this](const ogf::velodyne_packets_t& b, const lcm::ReceiveBuffer&, const std::string&) { onPackets(b); },
        malformed);
  } else {
    scan_sub_ = std::make_unique<transport::Subscriber<ogf::lidar_scan_t>>(
        lcm, source_.channel,
        [this](const ogf::lidar_scan_t& s, const lcm::ReceiveBuffer&, const std::string&) { onScan(s); }, malformed);
  }
}

void SourceIntake::unsubscribe() {
  scan_sub_.reset();
  packet_sub_.reset();
  idle_timer_.cancel();
}

void SourceIntake::restartInputWatch(std::int64_t steady_utime) {
  inputs_ = fusion::InputWatch(inputWatchConfig(), steady_utime);
}

const SourceIntake::Pending::Entry* SourceIntake::readyFront(std::int64_t now) {
  return staticPose() ? pending_.oldest() : pending_.readyFront(robot_.poses(), now);
}

void SourceIntake::scanMapped(std::int64_t measurements, const Eigen::Vector3d& sensor_origin) {
  ++mapped_.scans;
  mapped_.measurements += measurements;
  auto& trail = mapped_.trail;
  const Eigen::Vector3f at = sensor_origin.cast<float>();
  // The newest position always ends the trail; it replaces the last one while the sensor has not moved
  // kTrailSpacingM from the one before.
  if (trail.size() >= 2 && (trail[trail.size() - 2] - at).norm() < kTrailSpacingM) {
    trail.back() = at;
  } else {
    trail.push_back(at);
    if (trail.size() > kTrailPoints) trail.pop_front();
  }
}

void SourceIntake::onMalformed(const std::string& channel, std::size_t size, std::string_view why) {
  {
    std::lock_guard lk(shared_.mu);
    ++malformed_scans_;
    inputs_.scanArrived(steadyUtime());
  }
  if (auto n = bad_scan_log_.allow())
    spdlog::warn("{}{} on {} ({} bytes) {} ({} more)", label_, source_.packets ? "packets" : "scan", channel, size, why, *n);
}

void SourceIntake::onPackets(const ogf::velodyne_packets_t& batch) {
  std::int64_t rejected = 0;
  std::string why;
  std::int64_t offset = 0;
  for (std::int32_t i = 0; i < batch.num_packets; ++i) {
    const auto at = static_cast<std::size_t>(i);
    const std::int32_t length = batch.length[at];
    if (length < 0 || offset + length > batch.num_bytes) {
      rejected += batch.num_packets - i;
      why = "packet " + std::to_string(i) + ": length " + std::to_string(length) + " runs past the batch's " +
            std::to_string(batch.num_bytes) + " bytes";
      break;
    }
    const std::span<const std::uint8_t> payload(reinterpret_cast<const std::uint8_t*>(batch.data.data()) + offset,
                                                static_cast<std::size_t>(length));
    offset += length;
    // Data and position packets are told apart by their size (docs/wire-format.md): the batch's ports are
    // the receiving host's choice.
    bool taken = false;
    if (payload.size() == velodyne::wire::kDataPacketSize) {
      taken = packets_->addDataPacket(payload, batch.host_utime[at]) == velodyne::PacketStatus::Ok;
    } else if (payload.size() == velodyne::wire::kPositionPacketSize) {
      taken = packets_->addPositionPacket(payload, batch.host_utime[at]);
    }
    if (!taken) {
      ++rejected;
      if (why.empty()) why = "packet " + std::to_string(i) + " (" + std::to_string(length) + " bytes) refused by the decoder";
    }
  }
  last_batch_ = std::chrono::steady_clock::now();
  if (!idle_timer_armed_ && packets_->holdsScan()) armIdleTimer();
  {
    std::lock_guard lk(shared_.mu);
    packets_in_ += batch.num_packets;
    packets_rejected_ += rejected;
    inputs_.scanArrived(steadyUtime());
  }
  if (rejected > 0) {
    if (auto n = bad_scan_log_.allow())
      spdlog::warn("{}packets on {}: {} of {} refused, first: {} ({} more)", label_, source_.channel, rejected,
                   batch.num_packets, why, *n);
  }
}

void SourceIntake::armIdleTimer() {
  const double rpm = packets_->rpm() > 0.0f ? static_cast<double>(packets_->rpm()) : 600.0;
  const auto idle = std::chrono::microseconds(static_cast<std::int64_t>(kIdleScanPeriods * 60e6 / rpm));
  idle_timer_armed_ = true;
  idle_timer_.expires_at(last_batch_ + idle);
  idle_timer_.async_wait([this, idle](const boost::system::error_code& ec) {
    if (ec) return;  // cancelled: the source is going away
    idle_timer_armed_ = false;
    if (!packets_->holdsScan()) return;
    if (std::chrono::steady_clock::now() - last_batch_ < idle) {
      armIdleTimer();  // packets came since: due again after the latest
      return;
    }
    packets_->flushScan();
  });
}

bool SourceIntake::throttled(const ogf::lidar_scan_t& scan) {
  const auto model = static_cast<velodyne::Model>(scan.model);
  // A revolution's returns vary a little with the rate and the cut angle; a quarter more is not a sensor.
  const auto most = velodyne::mostPointsPerRevolution(model);
  if (!most || scan.num_points <= *most + *most / 4) return false;
  {
    std::lock_guard lk(shared_.mu);
    ++throttled_scans_;
    inputs_.scanArrived(steadyUtime());
  }
  if (auto n = throttle_log_.allow())
    spdlog::warn("{}scan seq {} throttled: {} points, more than one revolution of a {} holds ({} at 300 rpm, dual "
                 "return); a forged or misconfigured sender on {} ({} more)",
                 label_, scan.seq, scan.num_points, velodyne::modelName(model), *most, source_.channel, *n);
  return true;
}

void SourceIntake::onScan(const ogf::lidar_scan_t& scan) {
  if (auto st = adapters::validateScan(scan); !st) {
    {
      std::lock_guard lk(shared_.mu);
      ++malformed_scans_;
      inputs_.scanArrived(steadyUtime());
    }
    if (auto n = bad_scan_log_.allow())
      spdlog::warn("{}scan seq {} rejected: {} ({} more)", label_, scan.seq, st.error().message, *n);
    return;
  }
  if (throttled(scan)) return;
  auto owned = std::make_shared<const ogf::lidar_scan_t>(scan);
  const fusion::ScanTimeSpan span = fusion::timeSpanOf(adapters::scanPointsOf(*owned, source_.time_base));
  std::lock_guard lk(shared_.mu);
  const std::int64_t wall = wallUtime(), steady = steadyUtime();
  inputs_.scanArrived(steady);
  watchClocks(scan);  // before the time checks: a scan on another clock than the odometry is told apart
  const auto expected = clock_.expectedAt(steady);
  const auto verdict = clock_.check(span.end_utime, wall, steady);
  if (!timePlausible(label_ + "scan", verdict, clock_, expected, span.end_utime, wall, bad_time_log_)) return;
  if (verdict == fusion::TimeVerdict::kFollowJump) pending_.restartClock();
  const std::int64_t behind = pending_.counts().scans_dropped_behind;
  const fusion::ScanSpan queued{span.begin_utime, span.end_utime, static_cast<std::size_t>(scan.num_points)};
  const auto outcome = staticPose() ? pending_.pushFixedPose(queued, std::move(owned), steady)
                                    : pending_.push(queued, std::move(owned), robot_.poses(), steady);
  const auto& pending = options_.map.fusion.pending;
  if (outcome == fusion::PushOutcome::kLate) {
    if (auto n = bad_scan_log_.allow())
      spdlog::warn("{}scan seq {} arrived after a newer one: dropped ({} more)", label_, scan.seq, *n);
  } else if (outcome == fusion::PushOutcome::kTooLarge) {
    if (auto n = bad_scan_log_.allow())
      spdlog::warn(
          "{}scan seq {} has {} points, more than fusion.max_pending_points ({}) can hold: dropped, "
          "scans_dropped_behind ({} more)",
          label_, scan.seq, scan.num_points, pending.max_pending_points, *n);
  } else if (pending_.counts().scans_dropped_behind > behind) {
    // The queue was full of scans the worker had not taken yet: mapping is slower than the scans come.
    if (auto n = behind_log_.allow())
      spdlog::warn(
          "{}falling behind: a scan takes longer to map than the sensor takes to make one, so the oldest "
          "waiting scans are dropped to make room ({} so far, scans_dropped_behind; fusion.max_pending_scans "
          "{}). A coarser map.resolution, more filter.threads or, in compact storage, "
          "filter.stencil_manhattan_radius: 0 make each scan cheaper (docs/performance.md, \"When ogf-mapper "
          "falls behind\") ({} more)",
          label_, pending_.counts().scans_dropped_behind, pending.max_pending_scans, *n);
  }
  shared_.wake();
}

ogf::source_status_t SourceIntake::status(std::int64_t steady_now) const {
  ogf::source_status_t s{};
  s.name = source_.name;
  s.robot = source_.robot;
  s.scan_channel = source_.channel;
  s.packets = source_.packets;
  s.pose_channel = staticPose() ? std::string() : robot_.channel();
  s.inputs = inputsCode(inputs_.state());
  const auto age = [](std::optional<std::int64_t> us) { return us ? static_cast<float>(*us) * 1e-6f : -1.0f; };
  s.last_scan_age_s = age(inputs_.sinceScan(steady_now));
  s.last_pose_age_s = age(inputs_.sincePose(steady_now));
  fillClocks(s.clocks, s.scan_clock, s.clock_offset_us);
  const auto& pc = pending_.counts();
  s.scans_refused_time = clock_.counts().refused();
  s.scans_in = pc.scans_in + malformed_scans_ + s.scans_refused_time + throttled_scans_;
  s.scans_mapped = reported_.scans;
  s.scans_dropped_behind = pc.scans_dropped_behind;
  s.scans_dropped_no_pose = pc.scans_dropped_no_pose;
  s.scans_late = pc.scans_late;
  s.scans_rejected = pc.scans_rejected + malformed_scans_;
  s.scans_dropped_pose_jump = pc.scans_dropped_pose_jump;
  s.scans_throttled = throttled_scans_;
  s.measurements = reported_.measurements;
  s.packets_in = packets_in_;
  s.packets_rejected = packets_rejected_;
  const OdometryCounts odometry = robot_.counts();
  s.poses_in = odometry.poses_in;
  s.poses_rejected = odometry.poses_rejected;
  s.poses_refused_time = odometry.poses_refused_time;
  const auto& trail = reported_.trail;
  s.trail_size = static_cast<std::int16_t>(trail.size());
  s.trail.resize(trail.size());
  for (std::size_t i = 0; i < trail.size(); ++i) s.trail[i] = {trail[i].x(), trail[i].y(), trail[i].z()};
  return s;
}

}  // namespace ogf::mapper_daemon
