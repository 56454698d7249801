// ogf-driver: the Velodyne driver daemon. Reads the sensor over UDP (or a live interface, or a capture
// file), decodes scans and publishes them with the raw packets and a 1 Hz status on LCM.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include <cstdio>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "driver_app.hpp"
#include "driver_config.hpp"
#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"

namespace {

using ogf::driver::DriverConfig;
using ogf::driver::SourceKind;

// The command line: the configuration file, the source, and the flags that override the file's values
// (each option remembers whether it was given).
struct Flags {
  DriverConfig given;  // the flags' values, the defaults where a flag is absent
  std::string config_path, source;
  bool no_packets = false;
  CLI::Option *pcap = nullptr, *iface = nullptr, *speed = nullptr, *bind = nullptr, *data_port = nullptr,
              *position_port = nullptr, *sensor = nullptr, *rcvbuf = nullptr, *model = nullptr, *calib = nullptr,
              *mode = nullptr, *min_range = nullptr, *max_range = nullptr, *cut = nullptr, *frame = nullptr,
              *url = nullptr, *scan_ch = nullptr, *packets_ch = nullptr, *status_ch = nullptr, *level = nullptr;
};

void declareSourceFlags(CLI::App& app, Flags& f) {
  DriverConfig& d = f.given;
  app.add_option("--config", f.config_path, "YAML configuration file (flags override it)");
  app.add_option("--source", f.source, "udp, pcap-live or pcap-file")
      ->check(CLI::IsMember({"udp", "pcap-live", "pcap-file"}));
  f.pcap = app.add_option("--pcap", d.pcap_file, "Replay this capture file (implies --source pcap-file)")
               ->capture_default_str();
  f.iface = app.add_option("--interface", d.interface, "Capture live on this interface (implies pcap-live)")
                ->capture_default_str();
  f.speed = app.add_option("--speed", d.speed, "Capture-file pacing factor; 0 = as fast as possible")
                ->capture_default_str();
  f.bind = app.add_option("--bind-address", d.bind_address, "UDP bind address")->capture_default_str();
  f.data_port = app.add_option("--data-port", d.data_port, "Data packet port")->capture_default_str();
  f.position_port =
      app.add_option("--position-port", d.position_port, "Position packet port")->capture_default_str();
  f.sensor = app.add_option("--sensor-ip", d.sensor_address, "Accept packets only from this address")
                 ->capture_default_str();
  f.rcvbuf = app.add_option("--receive-buffer", d.receive_buffer_bytes, "SO_RCVBUF to ask for, bytes")
                 ->capture_default_str();
}

void declareDecodingFlags(CLI::App& app, Flags& f) {
  DriverConfig& d = f.given;
  f.model = app.add_option("--model", d.model, "auto, VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E")->capture_default_str();
  f.calib = app.add_option("--calib", d.calibration, "Calibration: VeloView XML or ROS YAML")->capture_default_str();
  f.mode = app.add_option("--return-mode", d.return_mode, "auto, strongest, last, dual")->capture_default_str();
  f.min_range =
      app.add_option("--min-range", d.min_range_m, "Minimum range, metres (0 keeps every non-zero return)")
          ->capture_default_str();
  f.max_range = app.add_option("--max-range", d.max_range_m, "Maximum range, metres")->capture_default_str();
  f.cut = app.add_option("--cut-angle", d.cut_angle_deg, "Scan cut azimuth, degrees clockwise from x")
              ->capture_default_str()
              ->check(ogf::cli::between(-360, 360));
  f.frame = app.add_option("--frame-id", d.frame_id, "Frame name in lidar_scan_t")->capture_default_str();
}

void declareOutputFlags(CLI::App& app, Flags& f) {
  DriverConfig& d = f.given;
  f.url = app.add_option("--lcm-url", d.lcm_url, "LCM URL (default $LCM_DEFAULT_URL or LCM's default)")
              ->capture_default_str();
  f.scan_ch = app.add_option("--scan-channel", d.scan_channel, "Channel of decoded scans")->capture_default_str();
  f.packets_ch = app.add_option("--packets-channel", d.packets_channel, "Channel of raw packet batches")
                     ->capture_default_str();
  f.status_ch =
      app.add_option("--status-channel", d.status_channel, "Channel of the 1 Hz status")->capture_default_str();
  app.add_flag("--no-packets", f.no_packets, "Do not publish raw packet batches");
  f.level = app.add_option("--log-level", d.log_level, "trace, debug, info, warn, error")->capture_default_str();
}

// Flags given on the command line override the file.
void applyFlags(const Flags& f, DriverConfig& config) {
  const DriverConfig& d = f.given;
  auto take = [](CLI::Option* option, auto& target, const auto& value) {
    if (option->count() > 0) target = value;
  };
  take(f.pcap, config.pcap_file, d.pcap_file);
  take(f.iface, config.interface, d.interface);
  take(f.speed, config.speed, d.speed);
  take(f.bind, config.bind_address, d.bind_address);
  take(f.data_port, config.data_port, d.data_port);
  take(f.position_port, config.position_port, d.position_port);
  take(f.sensor, config.sensor_address, d.sensor_address);
  take(f.rcvbuf, config.receive_buffer_bytes, d.receive_buffer_bytes);
  take(f.model, config.model, d.model);
  take(f.calib, config.calibration, d.calibration);
  take(f.mode, config.return_mode, d.return_mode);
  take(f.min_range, config.min_range_m, d.min_range_m);
  take(f.max_range, config.max_range_m, d.max_range_m);
  take(f.cut, config.cut_angle_deg, d.cut_angle_deg);
  take(f.frame, config.frame_id, d.frame_id);
  take(f.url, config.lcm_url, d.lcm_url);
  take(f.scan_ch, config.scan_channel, d.scan_channel);
  take(f.packets_ch, config.packets_channel, d.packets_channel);
  take(f.status_ch, config.status_channel, d.status_channel);
  take(f.level, config.log_level, d.log_level);
  if (f.no_packets) config.publish_packets = false;
  if (f.pcap->count() > 0) config.source = SourceKind::PcapFile;
  if (f.iface->count() > 0) config.source = SourceKind::PcapLive;
  if (f.source == "udp") config.source = SourceKind::Udp;
  if (f.source == "pcap-live") config.source = SourceKind::PcapLive;
  if (f.source == "pcap-file") config.source = SourceKind::PcapFile;
}

// The configuration: the file's values, then the flags'; the file's error when it is refused.
ogf::Result<DriverConfig> readConfig(const Flags& f) {
  DriverConfig config;
  if (!f.config_path.empty()) {
    auto loaded = ogf::driver::loadDriverConfig(f.config_path, config);
    if (!loaded) return loaded.error();
    config = std::move(*loaded);
  }
  applyFlags(f, config);
  return config;
}

// The packet stream the configuration describes; the reason when the configuration is invalid.
ogf::Result<ogf::velodyne::PacketStream> openStream(const DriverConfig& config) {
  auto stream_config = ogf::driver::validate(config);
  if (!stream_config) return stream_config.error();
  return ogf::velodyne::PacketStream::create(*stream_config);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ogf-driver: Velodyne VLP-16 / Puck Hi-Res / VLP-32C / HDL-32E driver on LCM.\n"
      "Publishes VELODYNE_SCAN (ogf.lidar_scan_t, one per revolution, cut at --cut-angle), VELODYNE_PACKETS\n"
      "(ogf.velodyne_packets_t, the raw payloads of each scan, for lcm-logger) and VELODYNE_STATUS\n"
      "(ogf.driver_status_t, 1 Hz). Settings come from --config (YAML, keys as the flags with '_', except\n"
      "pcap_file, sensor_address, receive_buffer_bytes, calibration and publish_packets: false for --pcap,\n"
      "--sensor-ip, --receive-buffer, --calib and --no-packets) and then the flags. Sources: UDP (default),\n"
      "--interface (live capture, needs CAP_NET_RAW) or --pcap FILE."};
  Flags flags;
  declareSourceFlags(app, flags);
  declareDecodingFlags(app, flags);
  declareOutputFlags(app, flags);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  auto config = readConfig(flags);
  if (!config) {
    std::fprintf(stderr, "ogf-driver: %s\n", config.error().message.c_str());
    return ogf::cli::exitCodeFor(config.error());
  }
  if (!ogf::transport::setupLoggingAt("ogf-driver", "log_level", config->log_level)) return ogf::cli::kExitUsage;
  auto stream = openStream(*config);
  if (!stream) {
    spdlog::error("configuration: {}", stream.error().message);
    return ogf::cli::exitCodeFor(stream.error());
  }
  const std::string lcm_url = ogf::transport::resolveLcmUrl(config->lcm_url);
  lcm::LCM lcm(lcm_url);  // publish only: no subscription, so LCM starts no receive thread
  if (!lcm.good()) {
    spdlog::error(
        "cannot open the LCM bus {} (udpm needs a multicast route; see scripts/multicast-loopback.sh)",
        lcm_url);
    return 1;
  }
  ogf::transport::DaemonLoop loop;
  ogf::driver::DriverApp driver(loop, lcm, *config, std::move(*stream));
  if (auto error = driver.start()) {
    spdlog::error("{}", error->message);
    return ogf::cli::exitCodeFor(*error);
  }
  loop.onShutdown([&driver] { driver.finish(); });
  loop.ready("decoding");
  return loop.run();
}
