// The capture loop: packets in time order into the pcap.
#include "ogf/sim/capture_writer.hpp"

#include <cmath>

#include "ogf/sim/pcap_writer.hpp"
#include "ogf/sim/position_packet.hpp"

namespace ogf::sim {

std::uint64_t dataPacketCount(const LidarSimulator& sim, double duration_s) {
  const auto duration_ns = static_cast<std::int64_t>(std::llround(duration_s * 1e9));
  if (duration_ns <= 0) return 0;
  return static_cast<std::uint64_t>((duration_ns - 1) / sim.packetPeriodNs() + 1);
}

Result<CaptureSummary> writeCapture(const LidarSimulator& sim, double duration_s, const std::string& pcap_path,
                                    const GeoPosition& where) {
  auto writer = PcapWriter::open(pcap_path);
  if (!writer) return Error{writer.error().message};
  CaptureSummary summary;
  const std::uint64_t count = dataPacketCount(sim, duration_s);
  std::array<std::uint8_t, vlp16::kDataPayloadBytes> payload{};
  for (std::uint64_t k = 0; k < count; ++k) {
    const std::int64_t t = sim.packetStartNs(k);
    vlp16::encode(sim.dataPacket(k), payload);
    if (auto s = writer->writeUdp(sim.utimeAt(t), vlp16::kDataPort, payload); !s) return Error{s.error().message};
    if (k == 0) summary.first_utime = sim.utimeAt(t);
    summary.last_utime = sim.utimeAt(t);
    ++summary.data_packets;
    if (k % kDataPacketsPerPositionPacket == kDataPacketsPerPositionPacket - 1) {
      // Half a period after the data packet, so frames stay in time order.
      const std::int64_t tp = t + sim.packetPeriodNs() / 2;
      const auto position = vlp16::encodePositionPacket(sim.tohAt(tp), vlp16::kPpsLocked,
                                                        gprmcSentence(sim.utimeAt(tp), where));
      if (auto s = writer->writeUdp(sim.utimeAt(tp), vlp16::kPositionPort, position); !s) return Error{s.error().message};
      ++summary.position_packets;
    }
  }
  if (auto s = writer->close(); !s) return Error{s.error().message};
  return summary;
}

}  // namespace ogf::sim
