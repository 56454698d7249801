// ogf-driver's configuration: every setting with its default, read from a YAML file and then overridden
// by flags, and validated at start-up with a message that names the setting.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ogf/velodyne/packet_stream.hpp"
#include "ogf/common/result.hpp"

namespace ogf::driver {

enum class SourceKind { Udp, PcapLive, PcapFile };

struct DriverConfig {
  SourceKind source = SourceKind::Udp;
  std::string pcap_file;  // source pcap-file
  std::string interface;  // source pcap-live
  double speed = 1.0;     // pcap-file pacing: capture time / speed; 0 = as fast as possible
  std::string bind_address = "0.0.0.0";
  int data_port = 2368;
  int position_port = 8308;
  std::string sensor_address;  // accept only this sender ("" = any)
  int receive_buffer_bytes = 8 * 1024 * 1024;

  std::string model = "auto";  // auto, VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E
  std::string calibration;     // VeloView XML or ROS YAML; "" = nominal
  std::string return_mode = "auto";
  double min_range_m = 0.4;
  double max_range_m = 250.0;
  double cut_angle_deg = 0.0;
  std::string frame_id = "velodyne";

  std::string lcm_url;  // "" = $LCM_DEFAULT_URL or LCM's default
  std::string scan_channel = "VELODYNE_SCAN";
  std::string packets_channel = "VELODYNE_PACKETS";
  std::string status_channel = "VELODYNE_STATUS";
  bool publish_packets = true;
  std::string log_level = "info";
};

// Reads the YAML file over `config`; unknown keys and wrong types are errors naming file, line and key.
ogf::Result<DriverConfig> loadDriverConfig(const std::string& path, DriverConfig config);
// The same from YAML text; `path` only names the source in errors.
ogf::Result<DriverConfig> parseDriverConfig(const std::string& yaml, const std::string& path, DriverConfig config);

// Checks ranges and names, loads the calibration, and builds the decoding configuration.
ogf::Result<velodyne::StreamConfig> validate(const DriverConfig& config);

const char* sourceName(SourceKind kind);

}  // namespace ogf::driver
