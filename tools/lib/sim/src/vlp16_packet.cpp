// The VLP-16 data packet encoder: 12 blocks of (flag, azimuth, 32 × (distance, reflectivity)), then the
// TOH stamp, the return-mode byte and the product id (docs/wire-format.md §3.1).
#include "ogf/sim/vlp16_packet.hpp"

#include "ogf/sim/byte_writer.hpp"

namespace ogf::sim::vlp16 {

void encode(const DataPacket& packet, std::span<std::uint8_t, kDataPayloadBytes> out) {
  for (std::size_t b = 0; b < kBlocks; ++b) {
    const FiringBlock& block = packet.blocks[b];
    const std::size_t base = kBlockBytes * b;
    putLe16(out, base, kBlockFlag);
    putLe16(out, base + 2, block.azimuth);
    for (std::size_t c = 0; c < kChannelsPerBlock; ++c) {
      putLe16(out, base + 4 + 3 * c, block.distance[c]);
      out[base + 6 + 3 * c] = block.reflectivity[c];
    }
  }
  putLe32(out, kTimestampOffset, packet.toh_us);
  out[kReturnModeOffset] = static_cast<std::uint8_t>(packet.mode);
  out[kProductIdOffset] = packet.product_id;
}

}  // namespace ogf::sim::vlp16
