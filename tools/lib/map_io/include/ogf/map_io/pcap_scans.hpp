// The scans of raw Velodyne packets, decoded with the driver's own decoder (velodyne::PacketStream)
// exactly as ogf-decode and ogf-driver see them, handed to a visitor one at a time: from a capture file
// (driver_sources::PcapFileReader; a damaged tail ends the reading with a warning, what came before it is
// kept), from the packet batches of an LCM log (VELODYNE_PACKETS; gaps between batches are reported) or
// from the VelodyneScan messages of a ROS 2 bag (gaps between messages are reported).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <ogf/common/result.hpp>
#include <optional>
#include <string>

#include "ogf/map_io/scan_record.hpp"
#include "ogf/rosbag/rosbag2_storage.hpp"

namespace ogf::map_io {

struct PcapScanConfig {
  std::optional<std::filesystem::path> calibration;  // VeloView XML or ROS YAML; default: nominal table
  double min_range_m = 0.4;    // the decoder drops closer returns
  double max_range_m = 250.0;  // and farther ones (the mapper cuts rays at its own max range)
  int data_port = 2368;
  int position_port = 8308;
};

struct PcapScanCounts {
  std::int64_t scans = 0;
  std::int64_t points = 0;
  std::int64_t data_packets = 0;
  std::int64_t packets_lost = 0;
  std::int64_t bad_packets = 0;  // wrong size, bad block flag, bad azimuth
  std::string warning;           // a damaged capture: where reading stopped; batches of a log skipped
  std::string gaps;              // a log's missing batches ("" when none)
  std::string calibration;       // what decoded the packets, for the log: the --calib file or the built-in table
};

// `progress` (optional) receives an estimate of the fraction of the file read after each scan.
Result<PcapScanCounts> readPcapScans(const std::filesystem::path& path, const PcapScanConfig& config,
                                     const std::function<void(const ScanRecord&)>& visit,
                                     const std::function<void(double)>& progress = {});

// The same from the ogf.velodyne_packets_t batches on `channel` of an LCM log, with their host receive times.
Result<PcapScanCounts> readLcmLogPacketScans(const std::filesystem::path& path, const std::string& channel,
                                             const PcapScanConfig& config,
                                             const std::function<void(const ScanRecord&)>& visit,
                                             const std::function<void(double)>& progress = {});

// The same from the velodyne_msgs/msg/VelodyneScan messages on `topic` of a ROS 2 bag, with their packet
// stamps.
Result<PcapScanCounts> readRosbagPacketScans(const rosbag::Rosbag2Storage& bag, const std::string& topic,
                                             const PcapScanConfig& config,
                                             const std::function<void(const ScanRecord&)>& visit,
                                             const std::function<void(double)>& progress = {});

}  // namespace ogf::map_io
