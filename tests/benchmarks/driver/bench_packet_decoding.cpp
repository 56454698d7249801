// Google Benchmark: packet -> points on one core, for the decoder alone and for the whole stream (decode,
// device time, scan assembly), over the real VLP-16 and HDL-32E captures (packets read into memory
// first). Reports packets/s and points/s; the live VLP-16 rate is 754 packets/s single return.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "ogf/velodyne/packet_stream.hpp"

namespace ov = ogf::velodyne;
namespace os = ogf::driver_sources;

namespace {

struct Packets {
  std::vector<std::vector<std::uint8_t>> data;
  std::vector<std::int64_t> utime;
};

Packets load(const char* relative) {
  Packets p;
  const std::filesystem::path path = std::filesystem::path(OGF_SHARED_DIR) / relative;
  auto reader = os::PcapFileReader::open(path);
  if (!reader) return p;
  os::PcapRecord r;
  os::ReadStatus s;
  while ((s = (*reader)->next(r)) == os::ReadStatus::Datagram || s == os::ReadStatus::Skipped) {
    if (s != os::ReadStatus::Datagram || r.datagram.destination_port != 2368 ||
        r.datagram.payload.size() != 1206)
      continue;
    p.data.emplace_back(r.datagram.payload.begin(), r.datagram.payload.end());
    p.utime.push_back(r.datagram.utime);
  }
  return p;
}

const Packets& capture(int which) {
  static const Packets vlp16 = load("data/real/sampleShort.pcap");
  static const Packets dual = load("data/real/derived/nebula_vlp16_dual_1673400471837873222.DERIVED.pcap");
  static const Packets hdl32 = load("data/real/monterey-first-100-packets.pcap");
  return which == 0 ? vlp16 : which == 1 ? dual : hdl32;
}

void BM_PacketDecoder(benchmark::State& state) {
  const Packets& packets = capture(static_cast<int>(state.range(0)));
  if (packets.data.empty()) {
    state.SkipWithError("shared captures absent (../shared/data/real)");
    return;
  }
  ov::DecoderConfig config;
  config.model = state.range(0) == 2 ? ov::Model::Hdl32E : ov::Model::Vlp16;
  config.min_range_m = 0.0;
  const auto decoder = ov::PacketDecoder::create(config);
  auto out = std::make_unique<ov::DecodedPacket>();
  std::size_t i = 0;
  std::int64_t points = 0;
  for (auto _ : state) {
    decoder->decode(packets.data[i], *out);
    points += out->point_count;
    benchmark::DoNotOptimize(out->points[0]);
    if (++i == packets.data.size()) i = 0;
  }
  state.counters["packets/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PacketDecoder)->Arg(0)->Arg(1)->Arg(2)->ArgName("capture(0=vlp16,1=dual,2=hdl32e)");

void BM_PacketStream(benchmark::State& state) {
  const Packets& packets = capture(static_cast<int>(state.range(0)));
  if (packets.data.empty()) {
    state.SkipWithError("shared captures absent (../shared/data/real)");
    return;
  }
  ov::StreamConfig config;
  config.model = state.range(0) == 2 ? ov::Model::Hdl32E : ov::Model::Vlp16;
  config.min_range_m = 0.0;
  auto stream = ov::PacketStream::create(config);
  std::int64_t points = 0;
  stream->setScanSink(
      [&points](const ov::Scan& scan) { points += static_cast<std::int64_t>(scan.points.size()); });
  std::size_t i = 0;
  std::int64_t offset = 0;
  const std::int64_t span = packets.utime.back() - packets.utime.front() + 1000;
  for (auto _ : state) {
    // Replays the capture again and again, moving time forward so it looks like one long drive.
    stream->addDataPacket(packets.data[i], packets.utime[i] + offset);
    if (++i == packets.data.size()) {
      i = 0;
      offset += span;
    }
  }
  state.counters["packets/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["points/s"] = benchmark::Counter(static_cast<double>(points), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PacketStream)->Arg(0)->Arg(1)->Arg(2)->ArgName("capture(0=vlp16,1=dual,2=hdl32e)");

}  // namespace

BENCHMARK_MAIN();
