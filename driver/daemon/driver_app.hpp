// ogf-driver's work: takes datagrams from the configured source, feeds the decoding stream, publishes
// each scan (VELODYNE_SCAN), the raw packets of each scan (VELODYNE_PACKETS) and a 1 Hz status
// (VELODYNE_STATUS), and counts and rate-limits the logging of every rejected input. On a live source
// (UDP, live capture) it publishes the scan in progress once no data packet has come for a few scan
// periods, so a pause in the sensor stream never holds a scan back until packets resume (ScanAssembler
// would drop it then).
#pragma once

#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>

#include "driver_config.hpp"
#include "ogf/driver_sources/live_capture.hpp"
#include "ogf/driver_sources/pcap_replay.hpp"
#include "ogf/driver_sources/udp_receiver.hpp"
#include "ogf/driver_status_t.hpp"
#include "ogf/lidar_scan_t.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "ogf/driver_messages/scan_message.hpp"

namespace ogf::driver {

class DriverApp {
 public:
  DriverApp(transport::DaemonLoop& loop, lcm::LCM& lcm, DriverConfig config, velodyne::PacketStream stream);

  // Opens the source and starts the status timer; an error names the source.
  std::optional<ogf::Error> start();
  // Publishes the scan in progress and a last status (end of a capture file, or shutdown).
  void finish();

 private:
  void onDatagram(const driver_sources::UdpDatagram& d);
  void onScan(const velodyne::Scan& scan);
  void onCaptureEnd(const std::string& error);
  void publishStatus();
  void armStatusTimer();
  // The idle check: due `idleAfter()` after the last data packet while a scan is in progress.
  void armIdleTimer();
  std::chrono::steady_clock::duration idleAfter() const;
  void logCalibration();
  void countMalformed(driver_sources::FrameKind kind);

  transport::DaemonLoop& loop_;
  lcm::LCM& lcm_;
  DriverConfig config_;
  velodyne::PacketStream stream_;
  std::uint32_t sensor_ip_ = 0;
  std::string source_description_;

  std::unique_ptr<driver_sources::UdpReceiver> data_socket_, position_socket_;
  std::unique_ptr<driver_sources::LiveCapture> live_;
  std::unique_ptr<driver_sources::PcapReplay> replay_;
  boost::asio::steady_timer status_timer_;
  boost::asio::steady_timer idle_timer_;
  bool idle_timer_armed_ = false;
  std::chrono::steady_clock::time_point last_data_time_;
  std::int64_t dropped_at_pause_logged_ = 0;
  bool calibration_logged_ = false;

  PacketBatch batch_;
  ogf::lidar_scan_t scan_msg_{};
  std::string current_sender_;
  std::uint32_t current_sender_ip_ = 0;

  std::int64_t foreign_sender_ = 0, other_port_ = 0, malformed_frames_ = 0;
  std::int64_t scans_published_ = 0, publish_errors_ = 0;
  std::int64_t last_status_packets_ = 0, last_status_scans_ = 0;
  std::chrono::steady_clock::time_point last_status_time_;
  bool finished_ = false;
  transport::LogRateLimiter size_log_, flag_log_, foreign_log_, other_log_;
};

}  // namespace ogf::driver
