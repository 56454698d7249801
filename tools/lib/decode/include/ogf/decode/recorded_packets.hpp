// The packets of a recorded capture handed to the driver's decoder (velodyne::PacketStream) as they were
// received: a pcap or pcapng file, an LCM log of the raw packet batches ogf-driver published, or a ROS 2
// bag's VelodyneScan messages. Packets to the data port are decoded, those to the position port read for
// time; the rest are counted. The caller ends the input with PacketStream::finish().
#pragma once

#include <cstdint>
#include <filesystem>
#include <ogf/common/result.hpp>
#include <string>
#include <vector>

#include "ogf/rosbag/rosbag2_storage.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace ogf::decode {

struct Ports {
  int data = 2368;      // the sensor's default data port (VLP-16 manual, "Network Configuration")
  int position = 8308;  // and position (GPS/PPS) port
};

struct FeedCounts {
  std::int64_t other_records = 0;     // pcap records that are not UDP datagrams
  std::int64_t fragments = 0;         // IP fragments, skipped
  std::int64_t cut_short = 0;         // records shorter than their datagram
  std::int64_t other_ports = 0;       // datagrams to neither port
  std::vector<std::string> warnings;  // what the input lacked or where it was damaged, in the order found
};

// A capture file; reading stops at damage, kept as a warning with the records read before it.
Result<FeedCounts> feedPcap(const std::filesystem::path& path, const Ports& ports,
                            velodyne::PacketStream& stream);

// The packet batches on `channel` of an LCM log.
Result<FeedCounts> feedPacketLog(const std::filesystem::path& path, const std::string& channel,
                                 const Ports& ports, velodyne::PacketStream& stream);

// The VelodyneScan packets of `topic` (data packets: a bag holds no position packets); `bag_name` names the
// bag in the warnings.
Result<FeedCounts> feedBagPackets(const rosbag::Rosbag2Storage& bag, const std::string& bag_name,
                                  const std::string& topic, velodyne::PacketStream& stream);

}  // namespace ogf::decode
