#include "capture_decoding.hpp"

namespace ogf::testing {

DecodedCapture decodeCapture(const std::filesystem::path& pcap, const velodyne::StreamConfig& config,
                             const std::function<bool(std::int64_t)>& keep) {
  DecodedCapture out;
  auto stream = velodyne::PacketStream::create(config);
  if (!stream) {
    out.read_error = stream.error().message;
    return out;
  }
  stream->setScanSink([&out](const velodyne::Scan& scan) { out.scans.push_back(scan); });
  auto reader = driver_sources::PcapFileReader::open(pcap);
  if (!reader) {
    out.read_error = reader.error().message;
    return out;
  }
  driver_sources::PcapRecord record;
  driver_sources::ReadStatus status;
  std::int64_t data_index = 0;
  while ((status = (*reader)->next(record)) == driver_sources::ReadStatus::Datagram ||
         status == driver_sources::ReadStatus::Skipped) {
    if (status != driver_sources::ReadStatus::Datagram) continue;
    const auto& d = record.datagram;
    if (d.destination_port == 2368) {
      if (!keep || keep(data_index)) stream->addDataPacket(d.payload, d.utime);
      ++data_index;
    } else if (d.destination_port == 8308) {
      stream->addPositionPacket(d.payload, d.utime);
    }
  }
  stream->finish();
  if (status == driver_sources::ReadStatus::Error) out.read_error = (*reader)->error();
  out.records = (*reader)->records();
  out.counters = stream->counters();
  out.model = stream->model();
  out.return_mode = stream->returnMode();
  out.last_position = stream->lastPosition();
  return out;
}

}  // namespace ogf::testing
