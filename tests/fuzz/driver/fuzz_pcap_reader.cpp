// libFuzzer target: the capture reader and link-layer parser on arbitrary files (pcap or pcapng, any link
// type), feeding what it finds into the decoding stream as ogf-decode does.
#include <cstdint>
#include <cstdio>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace os = ogf::driver_sources;
namespace ov = ogf::velodyne;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::FILE* file = ::fmemopen(const_cast<std::uint8_t*>(data), size, "rb");
  if (file == nullptr) return 0;
  auto reader = os::PcapFileReader::open(file, "fuzz");
  if (!reader) return 0;
  ov::StreamConfig config;
  config.assembler.reserve_points = 1024;
  auto stream = ov::PacketStream::create(config);
  if (!stream) return 0;
  os::PcapRecord record;
  for (int i = 0; i < 10000; ++i) {
    const os::ReadStatus status = (*reader)->next(record);
    if (status == os::ReadStatus::End || status == os::ReadStatus::Error) break;
    for (int link : {1, 113, 276, 101, 0}) (void)os::parseLinkFrame(link, record.datagram.payload);
    if (status != os::ReadStatus::Datagram) continue;
    if (record.datagram.destination_port == 2368)
      stream->addDataPacket(record.datagram.payload, record.datagram.utime);
    else if (record.datagram.destination_port == 8308)
      stream->addPositionPacket(record.datagram.payload, record.datagram.utime);
  }
  stream->finish();
  return 0;
}
