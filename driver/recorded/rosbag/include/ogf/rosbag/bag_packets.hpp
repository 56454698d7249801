// The raw Velodyne packets of a bag's velodyne_msgs/msg/VelodyneScan topic, one at a time in recorded
// order, each with its VelodynePacket stamp as the host receive time: what a pcap of the same stream holds,
// so they decode exactly as a capture does. A VelodyneScan does not carry position packets. Messages that
// do not decode, and damage the storage skips, are described; silences between messages (one per
// revolution) are gaps.
#pragma once

#include <cstdint>
#include <functional>
#include <ogf/common/result.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ogf/log_io/stream_gaps.hpp"
#include "ogf/rosbag/rosbag2_storage.hpp"

namespace ogf::rosbag {

struct BagPacket {
  std::int64_t host_utime = 0;            // the packet's stamp, microseconds
  std::span<const std::uint8_t> payload;  // 1206 bytes, the UDP payload the sensor sent to its data port
};

struct BagPacketCounts {
  std::int64_t messages = 0;          // VelodyneScan messages decoded
  std::int64_t packets = 0;           // handed to the visitor
  std::int64_t skipped = 0;           // messages that do not decode
  std::int64_t damaged = 0;           // damage the storage skipped (MCAP: chunks that do not check, a cut)
  std::vector<std::string> problems;  // the first few, naming file and row or byte offset
  log_io::StreamGaps gaps;            // of the messages, by bag timestamp
};

// The packet topic to read: `requested` when given (it must be a VelodyneScan topic of the bag), else the
// bag's only VelodyneScan topic; nullopt when the bag has none. An error asks for a choice (several
// topics) or names what is wrong with the requested one.
Result<std::optional<std::string>> choosePacketTopic(const Rosbag2Storage& bag, const std::string& requested);

// `progress` (optional) receives the fraction of the topic's messages read after each message.
Result<BagPacketCounts> readBagPackets(const Rosbag2Storage& bag, const std::string& topic,
                                       const std::function<void(const BagPacket&)>& visit,
                                       const std::function<void(double)>& progress = {});

}  // namespace ogf::rosbag
