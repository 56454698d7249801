#include "ogf/decode/recorded_packets.hpp"

#include <span>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/log_io/packet_log.hpp"
#include "ogf/rosbag/bag_packets.hpp"

namespace ogf::decode {
namespace {

namespace os = driver_sources;

void countSkipped(const os::PcapRecord& record, FeedCounts& counts) {
  if (record.kind == os::FrameKind::Fragment)
    ++counts.fragments;
  else if (record.kind == os::FrameKind::Truncated)
    ++counts.cut_short;
  else
    ++counts.other_records;
}

// A datagram to the data port is decoded, one to the position port read for time; others are counted.
void addPacket(int port, std::span<const std::uint8_t> payload, std::int64_t utime, const Ports& ports,
               velodyne::PacketStream& stream, FeedCounts& counts) {
  if (port == ports.data)
    stream.addDataPacket(payload, utime);
  else if (port == ports.position)
    stream.addPositionPacket(payload, utime);
  else
    ++counts.other_ports;
}

}  // namespace

Result<FeedCounts> feedPcap(const std::filesystem::path& path, const Ports& ports,
                            velodyne::PacketStream& stream) {
  auto reader = os::PcapFileReader::open(path);
  if (!reader) return Error{reader.error().message};
  FeedCounts counts;
  os::PcapRecord record;
  os::ReadStatus status;
  while ((status = (*reader)->next(record)) != os::ReadStatus::End && status != os::ReadStatus::Error) {
    if (status == os::ReadStatus::Skipped) {
      countSkipped(record, counts);
      continue;
    }
    const os::UdpDatagram& d = record.datagram;
    addPacket(d.destination_port, d.payload, d.utime, ports, stream, counts);
  }
  if (status == os::ReadStatus::Error)
    counts.warnings.push_back((*reader)->error() + "; kept the " + std::to_string((*reader)->records()) +
                              " records before it");
  return counts;
}

Result<FeedCounts> feedPacketLog(const std::filesystem::path& path, const std::string& channel,
                                 const Ports& ports, velodyne::PacketStream& stream) {
  FeedCounts counts;
  auto read = log_io::readPacketLog(path, channel, [&](const log_io::LoggedPacket& p) {
    addPacket(p.port, p.payload, p.host_utime, ports, stream, counts);
  });
  if (!read) return read.error();
  counts.warnings = read->problems;
  if (read->batches == 0) counts.warnings.push_back(path.string() + ": no packet batches on " + channel);
  if (const auto gaps = read->gaps.summary(path.string() + ": " + channel + " batches"); !gaps.empty())
    counts.warnings.push_back(gaps);
  return counts;
}

Result<FeedCounts> feedBagPackets(const rosbag::Rosbag2Storage& bag, const std::string& bag_name,
                                  const std::string& topic, velodyne::PacketStream& stream) {
  auto read = rosbag::readBagPackets(
      bag, topic, [&](const rosbag::BagPacket& p) { stream.addDataPacket(p.payload, p.host_utime); });
  if (!read) return read.error();
  FeedCounts counts;
  counts.warnings = read->problems;
  if (const auto gaps = read->gaps.summary(bag_name + ": " + topic + " messages"); !gaps.empty())
    counts.warnings.push_back(gaps);
  return counts;
}

}  // namespace ogf::decode
