// libFuzzer target: the packet decoder, scan assembly, position packets and NMEA parsing on arbitrary
// bytes. The input is a sequence of records: one selector byte (bit 0: data or position packet; the first
// record's byte also picks the model and return mode) followed by up to one packet's bytes.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "ogf/velodyne/nmea_sentence.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace ov = ogf::velodyne;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> input(data, size);
  (void)ov::parseNmeaSentence(std::string_view(reinterpret_cast<const char*>(data), size));

  ov::StreamConfig config;
  const std::uint8_t first = input[0];
  static constexpr ov::Model kModels[] = {ov::Model::Vlp16, ov::Model::Vlp16HiRes, ov::Model::Vlp32C,
                                          ov::Model::Hdl32E};
  if ((first & 0x10) != 0) config.model = kModels[(first >> 1) & 3];
  if ((first & 0x20) != 0) config.return_mode = static_cast<ov::ReturnMode>(1 + (first >> 6) % 3);
  config.min_range_m = 0.0;
  config.assembler.reserve_points = 1024;
  auto stream = ov::PacketStream::create(config);
  if (!stream) return 0;
  std::size_t points = 0;
  stream->setScanSink([&points](const ov::Scan& scan) {
    for (const ov::ScanPoint& p : scan.points) points += p.ring;  // touch every point
  });
  std::size_t at = 0;
  std::int64_t host = 1'600'000'000'000'000;
  while (at < size) {
    const bool is_data = (input[at] & 1) != 0;
    ++at;
    const std::size_t want = is_data ? 1206 : 512;
    const std::size_t n = size - at < want ? size - at : want;
    const auto payload = input.subspan(at, n);
    if (is_data)
      stream->addDataPacket(payload, host);
    else
      stream->addPositionPacket(payload, host);
    host += 1327;
    at += n;
  }
  stream->finish();
  return points == SIZE_MAX ? 1 : 0;
}
