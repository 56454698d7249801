#include "driver_config.hpp"

#include <yaml-cpp/yaml.h>

#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "ogf/driver_sources/udp_datagram.hpp"
#include "ogf/velodyne/calibration.hpp"

namespace ogf::driver {
namespace {

ogf::Error at(const std::string& path, const YAML::Node& node, const std::string& key,
                   const std::string& what) {
  return ogf::Error::configuration(path + ":" + std::to_string(node.Mark().line + 1) + ": " + key + ": " + what);
}

}  // namespace

const char* sourceName(SourceKind kind) {
  switch (kind) {
    case SourceKind::Udp:
      return "udp";
    case SourceKind::PcapLive:
      return "pcap-live";
    case SourceKind::PcapFile:
      return "pcap-file";
  }
  return "udp";
}

ogf::Result<DriverConfig> loadDriverConfig(const std::string& path, DriverConfig config) {
  std::ifstream in(path);
  if (!in) return ogf::Error::configuration(path + ": cannot read the configuration file");
  std::ostringstream text;
  text << in.rdbuf();  // an empty file gives "", an empty configuration
  return parseDriverConfig(text.str(), path, std::move(config));
}

ogf::Result<DriverConfig> parseDriverConfig(const std::string& yaml, const std::string& path, DriverConfig c) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    return ogf::Error::configuration(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (root.IsNull()) return c;
  if (!root.IsMap()) return ogf::Error::configuration(path + ": not a YAML mapping");
  using Setter = std::function<void(const YAML::Node&)>;
  std::string source;
  const std::map<std::string, Setter> setters = {
      {"source", [&](const YAML::Node& n) { source = n.as<std::string>(); }},
      {"pcap_file", [&](const YAML::Node& n) { c.pcap_file = n.as<std::string>(); }},
      {"interface", [&](const YAML::Node& n) { c.interface = n.as<std::string>(); }},
      {"speed", [&](const YAML::Node& n) { c.speed = n.as<double>(); }},
      {"bind_address", [&](const YAML::Node& n) { c.bind_address = n.as<std::string>(); }},
      {"data_port", [&](const YAML::Node& n) { c.data_port = n.as<int>(); }},
      {"position_port", [&](const YAML::Node& n) { c.position_port = n.as<int>(); }},
      {"sensor_address", [&](const YAML::Node& n) { c.sensor_address = n.as<std::string>(); }},
      {"receive_buffer_bytes", [&](const YAML::Node& n) { c.receive_buffer_bytes = n.as<int>(); }},
      {"model", [&](const YAML::Node& n) { c.model = n.as<std::string>(); }},
      {"calibration", [&](const YAML::Node& n) { c.calibration = n.as<std::string>(); }},
      {"return_mode", [&](const YAML::Node& n) { c.return_mode = n.as<std::string>(); }},
      {"min_range", [&](const YAML::Node& n) { c.min_range_m = n.as<double>(); }},
      {"max_range", [&](const YAML::Node& n) { c.max_range_m = n.as<double>(); }},
      {"cut_angle", [&](const YAML::Node& n) { c.cut_angle_deg = n.as<double>(); }},
      {"frame_id", [&](const YAML::Node& n) { c.frame_id = n.as<std::string>(); }},
      {"lcm_url", [&](const YAML::Node& n) { c.lcm_url = n.as<std::string>(); }},
      {"scan_channel", [&](const YAML::Node& n) { c.scan_channel = n.as<std::string>(); }},
      {"packets_channel", [&](const YAML::Node& n) { c.packets_channel = n.as<std::string>(); }},
      {"status_channel", [&](const YAML::Node& n) { c.status_channel = n.as<std::string>(); }},
      {"publish_packets", [&](const YAML::Node& n) { c.publish_packets = n.as<bool>(); }},
      {"log_level", [&](const YAML::Node& n) { c.log_level = n.as<std::string>(); }},
  };
  for (const auto& entry : root) {
    if (!entry.first.IsScalar()) return at(path, entry.first, "?", "a setting's name must be a plain word");
    const std::string key = entry.first.Scalar();
    const auto setter = setters.find(key);
    if (setter == setters.end()) return at(path, entry.first, key, "unknown setting");
    try {
      setter->second(entry.second);
    } catch (const YAML::Exception&) {
      return at(path, entry.second, key, "wrong type");
    }
  }
  if (!source.empty()) {
    if (source == "udp")
      c.source = SourceKind::Udp;
    else if (source == "pcap-live")
      c.source = SourceKind::PcapLive;
    else if (source == "pcap-file")
      c.source = SourceKind::PcapFile;
    else
      return at(path, root["source"], "source", "not one of udp, pcap-live, pcap-file");
  }
  return c;
}

ogf::Result<velodyne::StreamConfig> validate(const DriverConfig& c) {
  velodyne::StreamConfig s;
  if (c.source == SourceKind::PcapFile && c.pcap_file.empty())
    return ogf::Error::configuration("pcap_file: needed by source pcap-file");
  if (c.source == SourceKind::PcapLive && c.interface.empty())
    return ogf::Error::configuration("interface: needed by source pcap-live");
  if (!(c.speed >= 0.0)) return ogf::Error::configuration("speed: must be >= 0 (0 = as fast as possible)");
  if (c.data_port < 1 || c.data_port > 65535) return ogf::Error::configuration("data_port: not a port number");
  if (c.position_port < 1 || c.position_port > 65535 || c.position_port == c.data_port)
    return ogf::Error::configuration("position_port: not a port number distinct from data_port");
  std::uint32_t ip = 0;
  if (!c.sensor_address.empty() && !driver_sources::parseIpv4(c.sensor_address, ip))
    return ogf::Error::configuration("sensor_address: not an IPv4 address '" + c.sensor_address + "'");
  if (c.receive_buffer_bytes < 65536) return ogf::Error::configuration("receive_buffer_bytes: at least 65536");
  if (c.model != "auto") {
    s.model = velodyne::parseModelName(c.model);
    if (!s.model)
      return ogf::Error::configuration("model: '" + c.model +
                             "' is none of auto, VLP-16, VLP-16-HiRes, VLP-32C, HDL-32E");
  }
  if (c.return_mode != "auto") {
    s.return_mode = velodyne::parseReturnModeName(c.return_mode);
    if (!s.return_mode)
      return ogf::Error::configuration("return_mode: '" + c.return_mode + "' is none of auto, strongest, last, dual");
  }
  if (!c.calibration.empty()) {
    auto calib = velodyne::loadCalibrationFile(c.calibration);
    if (!calib) return ogf::Error::configuration("calibration: " + calib.error().message);
    s.calibration = std::move(*calib);
  }
  if (!(c.min_range_m >= 0.0) || !(c.max_range_m > c.min_range_m))
    return ogf::Error::configuration("min_range/max_range: need 0 <= min_range < max_range");
  s.min_range_m = c.min_range_m;
  s.max_range_m = c.max_range_m;
  if (!(c.cut_angle_deg >= -360.0 && c.cut_angle_deg <= 360.0))
    return ogf::Error::configuration("cut_angle: degrees in [-360, 360]");
  s.assembler.cut_angle_deg = c.cut_angle_deg;
  for (const auto* channel : {&c.scan_channel, &c.packets_channel, &c.status_channel})
    if (channel->empty() || channel->size() > 63) return ogf::Error::configuration("channel names: 1 to 63 characters");
  return s;
}

}  // namespace ogf::driver
