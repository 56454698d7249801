// Test helper: decodes a capture file with the driver library into scans (copied out of the stream) and
// the stream's final state, the same way ogf-decode does.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace ogf::testing {

struct DecodedCapture {
  std::vector<velodyne::Scan> scans;
  velodyne::StreamCounters counters;
  std::optional<velodyne::Model> model;
  std::optional<velodyne::ReturnMode> return_mode;
  std::optional<velodyne::PositionPacket> last_position;
  std::string read_error;  // "" when the file ended cleanly
  std::int64_t records = 0;
};

// `keep` decides per data datagram (0-based among data packets) whether it is fed; default: all.
DecodedCapture decodeCapture(const std::filesystem::path& pcap, const velodyne::StreamConfig& config = {},
                             const std::function<bool(std::int64_t)>& keep = {});

}  // namespace ogf::testing
