// ogf-driver: the Velodyne driver daemon. Reads the sensor over UDP (or a live interface, or a capture
// file), decodes scans and publishes them with the raw packets and a 1 Hz status on LCM.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include "ogf/common/command_line.hpp"
#include "driver_app.hpp"
#include "driver_config.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"

int main(int argc, char** argv) {
  using ogf::driver::DriverConfig;
  using ogf::driver::SourceKind;
  CLI::App app{
      "ogf-driver: Velodyne VLP-16 / Puck Hi-Res / VLP-32C / HDL-32E driver on LCM.\n"
      "Publishes VELODYNE_SCAN (ogf.lidar_scan_t, one per revolution, cut at --cut-angle), VELODYNE_PACKETS\n"
      "(ogf.velodyne_packets_t, the raw payloads of each scan, for lcm-logger) and VELODYNE_STATUS\n"
      "(ogf.driver_status_t, 1 Hz). Settings come from --config (YAML, keys as the flags with '_', except\n"
      "pcap_file, sensor_address, receive_buffer_bytes, calibration and publish_packets: false for --pcap,\n"
      "--sensor-ip, --receive-buffer, --calib and --no-packets) and then the flags. Sources: UDP (default),\n"
      "--interface (live capture, needs CAP_NET_RAW) or --pcap FILE."};
  DriverConfig defaults;
  std::string config_path, source;
  app.add_option("--config", config_path, "YAML configuration file (flags override it)");
  app.add_option("--source", source, "udp, pcap-live or pcap-file")
      ->check(CLI::IsMember({"udp", "pcap-live", "pcap-file"}));
  auto* pcap =
      app.add_option("--pcap", defaults.pcap_file, "Replay this capture file (implies --source pcap-file)")
          ->capture_default_str();
  auto* iface =
      app.add_option("--interface", defaults.interface, "Capture live on this interface (implies pcap-live)")
          ->capture_default_str();
  auto* speed =
      app.add_option("--speed", defaults.speed, "Capture-file pacing factor; 0 = as fast as possible")
          ->capture_default_str();
  auto* bind =
      app.add_option("--bind-address", defaults.bind_address, "UDP bind address")->capture_default_str();
  auto* data_port =
      app.add_option("--data-port", defaults.data_port, "Data packet port")->capture_default_str();
  auto* position_port = app.add_option("--position-port", defaults.position_port, "Position packet port")
                            ->capture_default_str();
  auto* sensor =
      app.add_option("--sensor-ip", defaults.sensor_address, "Accept packets only from this address")
          ->capture_default_str();
  auto* rcvbuf =
      app.add_option("--receive-buffer", defaults.receive_buffer_bytes, "SO_RCVBUF to ask for, bytes")
          ->capture_default_str();
  auto* model = app.add_option("--model", defaults.model, "auto, VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E")
                    ->capture_default_str();
  auto* calib = app.add_option("--calib", defaults.calibration, "Calibration: VeloView XML or ROS YAML")
                    ->capture_default_str();
  auto* mode = app.add_option("--return-mode", defaults.return_mode, "auto, strongest, last, dual")
                   ->capture_default_str();
  auto* min_range = app.add_option("--min-range", defaults.min_range_m,
                                   "Minimum range, metres (0 keeps every non-zero return)")
                        ->capture_default_str();
  auto* max_range =
      app.add_option("--max-range", defaults.max_range_m, "Maximum range, metres")->capture_default_str();
  auto* cut =
      app.add_option("--cut-angle", defaults.cut_angle_deg, "Scan cut azimuth, degrees clockwise from x")
          ->capture_default_str()
          ->check(ogf::cli::between(-360, 360));
  auto* frame =
      app.add_option("--frame-id", defaults.frame_id, "Frame name in lidar_scan_t")->capture_default_str();
  auto* url =
      app.add_option("--lcm-url", defaults.lcm_url, "LCM URL (default $LCM_DEFAULT_URL or LCM's default)")
          ->capture_default_str();
  auto* scan_ch = app.add_option("--scan-channel", defaults.scan_channel, "Channel of decoded scans")
                      ->capture_default_str();
  auto* packets_ch =
      app.add_option("--packets-channel", defaults.packets_channel, "Channel of raw packet batches")
          ->capture_default_str();
  auto* status_ch = app.add_option("--status-channel", defaults.status_channel, "Channel of the 1 Hz status")
                        ->capture_default_str();
  bool no_packets = false;
  app.add_flag("--no-packets", no_packets, "Do not publish raw packet batches");
  auto* level = app.add_option("--log-level", defaults.log_level, "trace, debug, info, warn, error")
                    ->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  DriverConfig config;
  if (!config_path.empty()) {
    auto loaded = ogf::driver::loadDriverConfig(config_path, config);
    if (!loaded) {
      std::fprintf(stderr, "ogf-driver: %s\n", loaded.error().message.c_str());
      return ogf::cli::exitCodeFor(loaded.error());
    }
    config = std::move(*loaded);
  }
  // Flags given on the command line override the file.
  auto take = [](CLI::Option* option, auto& target, const auto& value) {
    if (option->count() > 0) target = value;
  };
  take(pcap, config.pcap_file, defaults.pcap_file);
  take(iface, config.interface, defaults.interface);
  take(speed, config.speed, defaults.speed);
  take(bind, config.bind_address, defaults.bind_address);
  take(data_port, config.data_port, defaults.data_port);
  take(position_port, config.position_port, defaults.position_port);
  take(sensor, config.sensor_address, defaults.sensor_address);
  take(rcvbuf, config.receive_buffer_bytes, defaults.receive_buffer_bytes);
  take(model, config.model, defaults.model);
  take(calib, config.calibration, defaults.calibration);
  take(mode, config.return_mode, defaults.return_mode);
  take(min_range, config.min_range_m, defaults.min_range_m);
  take(max_range, config.max_range_m, defaults.max_range_m);
  take(cut, config.cut_angle_deg, defaults.cut_angle_deg);
  take(frame, config.frame_id, defaults.frame_id);
  take(url, config.lcm_url, defaults.lcm_url);
  take(scan_ch, config.scan_channel, defaults.scan_channel);
  take(packets_ch, config.packets_channel, defaults.packets_channel);
  take(status_ch, config.status_channel, defaults.status_channel);
  take(level, config.log_level, defaults.log_level);
  if (no_packets) config.publish_packets = false;
  if (pcap->count() > 0) config.source = SourceKind::PcapFile;
  if (iface->count() > 0) config.source = SourceKind::PcapLive;
  if (source == "udp") config.source = SourceKind::Udp;
  if (source == "pcap-live") config.source = SourceKind::PcapLive;
  if (source == "pcap-file") config.source = SourceKind::PcapFile;

  if (!ogf::transport::setupLoggingAt("ogf-driver", "log_level", config.log_level)) return 2;
  auto stream_config = ogf::driver::validate(config);
  if (!stream_config) {
    spdlog::error("configuration: {}", stream_config.error().message);
    return ogf::cli::exitCodeFor(stream_config.error());
  }
  auto stream = ogf::velodyne::PacketStream::create(*stream_config);
  if (!stream) {
    spdlog::error("configuration: {}", stream.error().message);
    return ogf::cli::exitCodeFor(stream.error());
  }
  const std::string lcm_url = ogf::transport::resolveLcmUrl(config.lcm_url);
  lcm::LCM lcm(lcm_url);  // publish only: no subscription, so LCM starts no receive thread
  if (!lcm.good()) {
    spdlog::error(
        "cannot open the LCM bus {} (udpm needs a multicast route; see scripts/multicast-loopback.sh)",
        lcm_url);
    return 1;
  }
  ogf::transport::DaemonLoop loop;
  ogf::driver::DriverApp driver(loop, lcm, config, std::move(*stream));
  if (auto error = driver.start()) {
    spdlog::error("{}", error->message);
    return ogf::cli::exitCodeFor(*error);
  }
  loop.onShutdown([&driver] { driver.finish(); });
  loop.ready("decoding");
  return loop.run();
}
