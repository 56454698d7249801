// The raw packets of an LCM log's VELODYNE_PACKETS channel (ogf.velodyne_packets_t batches, as ogf-driver
// publishes them and lcm-logger records them), handed one at a time in recorded order with their host
// receive time and UDP port, so they decode again exactly as the driver decoded them live. Batches that do
// not decode, or whose lengths disagree with their bytes, are skipped and counted; silences between
// batches are gaps.
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "ogf/log_io/stream_gaps.hpp"

namespace ogf::log_io {

struct LoggedPacket {
  std::int64_t host_utime = 0;
  int port = 0;
  std::span<const std::uint8_t> payload;
};

struct PacketLogCounts {
  std::int64_t events = 0;   // every event in the log
  std::int64_t batches = 0;  // velodyne_packets_t decoded
  std::int64_t packets = 0;  // handed to the visitor
  std::int64_t skipped = 0;  // batches on the channel that do not decode or are inconsistent
  std::vector<std::string> problems;  // the first few, naming file and event number
  StreamGaps gaps;           // of the batches (one per scan)
};

// `progress` (optional) receives the fraction of the file read after each batch.
Result<PacketLogCounts> readPacketLog(const std::filesystem::path& path, const std::string& channel,
                                      const std::function<void(const LoggedPacket&)>& visit,
                                      const std::function<void(double)>& progress = {});

}  // namespace ogf::log_io
