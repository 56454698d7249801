#include "driver_app.hpp"

#include <spdlog/spdlog.h>
#include <sys/time.h>

#include <algorithm>

namespace ogf::driver {
namespace {

std::int64_t nowUtime() {
  timeval tv{};
  ::gettimeofday(&tv, nullptr);
  return static_cast<std::int64_t>(tv.tv_sec) * 1'000'000 + tv.tv_usec;
}

// Scan periods without a data packet after which the stream is idle and the scan in progress goes out:
// three lets a burst of lost packets (20 ms ends a scan already) pass for packet loss, and at the slowest
// rotation (300 rpm, 0.2 s a turn) stays under ScanAssemblerConfig::pause_us.
constexpr double kIdleScanPeriods = 3.0;

}  // namespace

DriverApp::DriverApp(transport::DaemonLoop& loop, lcm::LCM& lcm, DriverConfig config,
                     velodyne::PacketStream stream)
    : loop_(loop),
      lcm_(lcm),
      config_(std::move(config)),
      stream_(std::move(stream)),
      status_timer_(loop.io()),
      idle_timer_(loop.io()) {
  if (!config_.sensor_address.empty()) driver_sources::parseIpv4(config_.sensor_address, sensor_ip_);
  stream_.setScanSink([this](const velodyne::Scan& scan) { onScan(scan); });
}

std::optional<ogf::Error> DriverApp::start() {
  const auto data_port = static_cast<std::uint16_t>(config_.data_port);
  const auto position_port = static_cast<std::uint16_t>(config_.position_port);
  auto handler = [this](const driver_sources::UdpDatagram& d) { onDatagram(d); };
  switch (config_.source) {
    case SourceKind::Udp: {
      driver_sources::UdpReceiverConfig rc{config_.bind_address, data_port, config_.receive_buffer_bytes};
      auto data = driver_sources::UdpReceiver::open(loop_.io(), rc, handler);
      if (!data) return data.error();
      rc.port = position_port;
      auto position = driver_sources::UdpReceiver::open(loop_.io(), rc, handler);
      if (!position) return position.error();
      data_socket_ = std::move(*data);
      position_socket_ = std::move(*position);
      // Linux grants at most net.core.rmem_max.
      if (data_socket_->grantedReceiveBuffer() < static_cast<std::int64_t>(config_.receive_buffer_bytes))
        spdlog::warn(
            "the kernel granted a {} byte receive buffer, less than the {} asked for: net.core.rmem_max caps "
            "it; raise it (sysctl -w net.core.rmem_max={}) or bursts may be dropped",
            data_socket_->grantedReceiveBuffer(), config_.receive_buffer_bytes,
            config_.receive_buffer_bytes);
      source_description_ = "udp " + config_.bind_address + ":" + std::to_string(data_socket_->port());
      break;
    }
    case SourceKind::PcapLive: {
      auto live = driver_sources::LiveCapture::open(
          loop_.io(), config_.interface, data_port, position_port,
          [this](driver_sources::FrameKind kind, const driver_sources::UdpDatagram& d) {
            if (kind == driver_sources::FrameKind::Udp)
              onDatagram(d);
            else
              countMalformed(kind);
          });
      if (!live) return live.error();
      live_ = std::move(*live);
      source_description_ = "pcap-live " + config_.interface;
      break;
    }
    case SourceKind::PcapFile: {
      auto reader = driver_sources::PcapFileReader::open(config_.pcap_file);
      if (!reader) return reader.error();
      replay_ = std::make_unique<driver_sources::PcapReplay>(
          loop_.io(), std::move(*reader), config_.speed,
          [this](const driver_sources::PcapRecord& r) {
            if (r.kind == driver_sources::FrameKind::Udp)
              onDatagram(r.datagram);
            else
              countMalformed(r.kind);
          },
          [this](const std::string& error) { onCaptureEnd(error); });
      replay_->start();
      source_description_ = "pcap-file " + config_.pcap_file;
      break;
    }
  }
  last_status_time_ = std::chrono::steady_clock::now();
  armStatusTimer();
  logCalibration();
  spdlog::info("reading {}; publishing {}, {}{} on the LCM bus", source_description_, config_.scan_channel,
               config_.status_channel,
               config_.publish_packets ? ", " + config_.packets_channel : std::string());
  return std::nullopt;
}

void DriverApp::countMalformed(driver_sources::FrameKind kind) {
  // Frames that are not UDP at all (ARP, IPv6) are not the sensor's and not an error.
  if (kind == driver_sources::FrameKind::NotUdp) return;
  ++malformed_frames_;
  if (auto n = other_log_.allow())
    spdlog::warn("skipped a captured frame that is {} ({} more since the last report)",
                 kind == driver_sources::FrameKind::Fragment ? "an IPv4 fragment"
                                                             : "cut short or of an unknown link type",
                 *n);
}

void DriverApp::onDatagram(const driver_sources::UdpDatagram& d) {
  if (sensor_ip_ != 0 && d.source_ip != sensor_ip_) {
    ++foreign_sender_;
    if (auto n = foreign_log_.allow())
      spdlog::warn("ignored a datagram from {} on port {}: not the sensor {} ({} more since the last report)",
                   driver_sources::formatIpv4(d.source_ip), d.destination_port, config_.sensor_address, *n);
    return;
  }
  const bool data = d.destination_port == config_.data_port;
  const bool position = d.destination_port == config_.position_port;
  if (!data && !position) {
    ++other_port_;
    return;
  }
  const velodyne::StreamCounters before = stream_.counters();
  // Raw packets go into the batch before decoding, so the batch published with a scan holds the packet
  // that completed it; only well-sized packets are logged raw.
  const std::size_t expected = data ? velodyne::wire::kDataPacketSize : velodyne::wire::kPositionPacketSize;
  if (config_.publish_packets && d.payload.size() == expected) {
    if (d.source_ip != current_sender_ip_) {
      current_sender_ip_ = d.source_ip;
      current_sender_ = driver_sources::formatIpv4(d.source_ip);
    }
    batch_.add(d.payload, d.utime, d.destination_port, current_sender_);
  }
  if (data)
    stream_.addDataPacket(d.payload, d.utime);
  else
    stream_.addPositionPacket(d.payload, d.utime);
  if (data) {
    if (!calibration_logged_) logCalibration();
    if (config_.source != SourceKind::PcapFile) {
      last_data_time_ = std::chrono::steady_clock::now();
      if (!idle_timer_armed_ && stream_.holdsScan()) armIdleTimer();
    }
    if (stream_.scansDroppedAtPause() > dropped_at_pause_logged_) {
      spdlog::warn("dropped {} scan(s) held open across a pause in the sensor stream (more than {:.1f} s without a "
                   "packet): they would have gone out late", stream_.scansDroppedAtPause() - dropped_at_pause_logged_,
                   stream_.config().assembler.pause_us / 1e6);
      dropped_at_pause_logged_ = stream_.scansDroppedAtPause();
    }
  }
  const velodyne::StreamCounters& after = stream_.counters();
  if (after.bad_size > before.bad_size) {
    if (auto n = size_log_.allow())
      spdlog::warn(
          "skipped a {} byte datagram on port {} from {}: expected {} ({} more since the last report)",
          d.payload.size(), d.destination_port, driver_sources::formatIpv4(d.source_ip), expected, *n);
  } else if (after.bad_block_flag > before.bad_block_flag) {
    if (auto n = flag_log_.allow())
      spdlog::warn("skipped a data packet from {} with a bad block flag ({} more since the last report)",
                   driver_sources::formatIpv4(d.source_ip), *n);
  } else if (after.bad_time_of_hour > before.bad_time_of_hour) {
    if (auto n = other_log_.allow())
      spdlog::warn("skipped a packet on port {} from {}: offset {} (timestamp) is past the hour ({} more since the "
                   "last report)", d.destination_port, driver_sources::formatIpv4(d.source_ip), data ? 1200 : 198, *n);
  } else if (after.unknown_return_mode > before.unknown_return_mode || after.unknown_model > before.unknown_model) {
    if (auto n = other_log_.allow())
      spdlog::warn("skipped a data packet from {}: offset {} holds 0x{:02x}, no known {} ({} more since the last "
                   "report)", driver_sources::formatIpv4(d.source_ip),
                   after.unknown_model > before.unknown_model ? 1205 : 1204,
                   d.payload[after.unknown_model > before.unknown_model ? 1205 : 1204],
                   after.unknown_model > before.unknown_model ? "product" : "return mode", *n);
  } else if (after.bad_position > before.bad_position) {
    if (auto n = other_log_.allow())
      spdlog::warn("skipped a malformed position packet from {} ({} more since the last report)",
                   driver_sources::formatIpv4(d.source_ip), *n);
  } else if (after.nmea_time_refused > before.nmea_time_refused) {
    if (auto n = other_log_.allow())
      spdlog::warn("position packet from {}: GPS time more than a day ahead of the host clock not used: '{}' ({} "
                   "more since the last report)", driver_sources::formatIpv4(d.source_ip),
                   stream_.lastPosition() ? std::string(stream_.lastPosition()->nmea()) : "", *n);
  } else if (after.bad_other > before.bad_other) {
    if (auto n = other_log_.allow())
      spdlog::warn("skipped a malformed packet on port {} ({} more since the last report)",
                   d.destination_port, *n);
  }
}

void DriverApp::onScan(const velodyne::Scan& scan) {
  fillScanMessage(scan, config_.frame_id, scan_msg_);
  if (lcm_.publish(config_.scan_channel, &scan_msg_) == 0)
    ++scans_published_;
  else
    ++publish_errors_;
  if (config_.publish_packets && !batch_.empty()) {
    if (lcm_.publish(config_.packets_channel, &batch_.message()) != 0) ++publish_errors_;
    batch_.clear();
  }
}

void DriverApp::onCaptureEnd(const std::string& error) {
  if (!error.empty()) {
    ++malformed_frames_;
    spdlog::warn("{}; every record before it was used", error);
  }
  spdlog::info("end of {}", config_.pcap_file);
  finish();
  loop_.requestStop(0);
}

void DriverApp::finish() {
  if (finished_) return;
  finished_ = true;
  stream_.finish();
  if (config_.publish_packets && !batch_.empty()) {
    if (lcm_.publish(config_.packets_channel, &batch_.message()) != 0) ++publish_errors_;
    batch_.clear();
  }
  publishStatus();
  status_timer_.cancel();
  idle_timer_.cancel();
}

void DriverApp::armStatusTimer() {
  status_timer_.expires_after(std::chrono::seconds(1));
  status_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || finished_) return;
    publishStatus();
    armStatusTimer();
  });
}

std::chrono::steady_clock::duration DriverApp::idleAfter() const {
  const double rpm = stream_.rpm() > 0.0f ? static_cast<double>(stream_.rpm()) : 600.0;
  const double idle_us = std::min(kIdleScanPeriods * 60e6 / rpm, stream_.config().assembler.pause_us / 2.0);
  return std::chrono::microseconds(static_cast<std::int64_t>(idle_us));
}

void DriverApp::armIdleTimer() {
  idle_timer_armed_ = true;
  idle_timer_.expires_at(last_data_time_ + idleAfter());
  idle_timer_.async_wait([this](const boost::system::error_code& ec) {
    idle_timer_armed_ = false;
    if (ec || finished_ || !stream_.holdsScan()) return;
    const auto now = std::chrono::steady_clock::now();
    const auto quiet = now - last_data_time_;
    if (data_socket_ && data_socket_->datagramWaiting()) {
      // Not idle: this process fell behind (descheduled, stopped) and packets wait to be read.
      last_data_time_ = now;
      armIdleTimer();
      return;
    }
    if (quiet < idleAfter()) {
      armIdleTimer();  // packets came since: due again after the latest
      return;
    }
    spdlog::info("no data packet for {} ms: the sensor stream is idle; publishing the scan in progress",
                 std::chrono::duration_cast<std::chrono::milliseconds>(quiet).count());
    stream_.flushScan();
  });
}

void DriverApp::logCalibration() {
  const auto model = stream_.model();
  if (calibration_logged_ || !model) return;
  calibration_logged_ = true;
  const std::string name(velodyne::modelName(*model));
  const char* how = config_.model == "auto" ? "detected" : "configured";
  if (config_.calibration.empty())
    spdlog::info("sensor model {} ({}); calibration: the embedded nominal {} table (no --calib or calibration "
                 "key given)", name, how, name);
  else
    spdlog::info("sensor model {} ({}); calibration: {}", name, how, config_.calibration);
}

void DriverApp::publishStatus() {
  const velodyne::StreamCounters& c = stream_.counters();
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - last_status_time_).count();
  ogf::driver_status_t s{};
  s.utime = nowUtime();
  s.source = source_description_;
  s.model = static_cast<std::int8_t>(stream_.model().value_or(velodyne::Model::Unknown));
  s.return_mode =
      static_cast<std::int8_t>(stream_.returnMode() ? static_cast<int>(*stream_.returnMode()) : 0);
  s.rpm = stream_.rpm();
  s.packet_rate_hz =
      elapsed > 0 ? static_cast<float>(static_cast<double>(c.data_packets - last_status_packets_) / elapsed)
                  : 0.0f;
  s.scan_rate_hz =
      elapsed > 0 ? static_cast<float>(static_cast<double>(scans_published_ - last_status_scans_) / elapsed)
                  : 0.0f;
  s.data_packets = c.data_packets;
  s.position_packets = c.position_packets;
  s.packets_lost = stream_.packetsLost();
  s.bad_size = c.bad_size;
  s.bad_block_flag = c.bad_block_flag;
  s.foreign_sender = foreign_sender_;
  s.bad_other = c.bad_other + malformed_frames_;
  s.bad_time_of_hour = c.bad_time_of_hour;
  s.unknown_return_mode = c.unknown_return_mode;
  s.unknown_model = c.unknown_model;
  s.bad_position = c.bad_position;
  s.nmea_time_refused = c.nmea_time_refused;
  s.scans_published = scans_published_;
  s.publish_errors = publish_errors_;
  s.pps_state = ogf::driver_status_t::PPS_UNKNOWN;
  s.gps_fix_valid = false;
  if (const auto& pos = stream_.lastPosition()) {
    s.pps_state = static_cast<std::int8_t>(pos->pps);
    s.gps_fix_valid = pos->gpsFixValid();
    s.nmea = std::string(pos->nmea());
  }
  s.socket_receive_buffer = data_socket_ ? data_socket_->grantedReceiveBuffer() : 0;
  s.kernel_drops = 0;
  for (const auto& socket : {data_socket_.get(), position_socket_.get()})
    if (socket != nullptr) s.kernel_drops += static_cast<std::int64_t>(socket->kernelDrops());
  if (live_) s.kernel_drops += static_cast<std::int64_t>(live_->kernelDrops());
  if (lcm_.publish(config_.status_channel, &s) != 0) ++publish_errors_;
  last_status_packets_ = c.data_packets;
  last_status_scans_ = scans_published_;
  last_status_time_ = now;
}

}  // namespace ogf::driver
