#include "ogf/driver_sources/link_layer.hpp"

namespace ogf::driver_sources {
namespace {

// LINKTYPE_* values (tcpdump.org/linktypes.html).
constexpr int kLinkNull = 0;
constexpr int kLinkEthernet = 1;
constexpr int kLinkRawOpenBsd = 12;
constexpr int kLinkRaw = 101;
constexpr int kLinkSll = 113;
constexpr int kLinkIpv4 = 228;
constexpr int kLinkSll2 = 276;

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherVlan = 0x8100;
constexpr std::uint16_t kEtherQinQ = 0x88a8;

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t be32(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
         (static_cast<std::uint32_t>(p[2]) << 8) | p[3];
}

LinkFrame parseIpv4(std::span<const std::uint8_t> ip) {
  LinkFrame out;
  if (ip.size() < 20) return {FrameKind::Truncated, {}};
  if ((ip[0] >> 4) != 4) return out;  // not IPv4
  const std::size_t header = static_cast<std::size_t>(ip[0] & 0x0f) * 4;
  if (header < 20 || ip.size() < header) return {FrameKind::Truncated, {}};
  const std::size_t total = be16(&ip[2]);
  if (total < header) return {FrameKind::Truncated, {}};
  if (ip[9] != 17) return out;  // not UDP
  const std::uint16_t fragment = be16(&ip[6]);
  if ((fragment & 0x2000) != 0 || (fragment & 0x1fff) != 0) return {FrameKind::Fragment, {}};
  // Early VLP-16 firmware writes a wrong IPv4 total length into position packets (1234 for a 554-byte
  // frame in vlp-16-test-90deg-1-50-frames.pcap): when it overshoots the frame, the UDP length decides.
  const std::size_t available = total <= ip.size() ? total : ip.size();
  const std::span<const std::uint8_t> udp = ip.subspan(header, available - header);
  if (udp.size() < 8) return {FrameKind::Truncated, {}};
  const std::size_t udp_length = be16(&udp[4]);
  if (udp_length < 8 || udp_length > udp.size()) return {FrameKind::Truncated, {}};
  out.kind = FrameKind::Udp;
  out.datagram.source_ip = be32(&ip[12]);
  out.datagram.source_port = be16(&udp[0]);
  out.datagram.destination_port = be16(&udp[2]);
  out.datagram.payload = udp.subspan(8, udp_length - 8);
  return out;
}

// An EtherType-tagged payload, after any VLAN tags.
LinkFrame parseEtherType(std::uint16_t type, std::span<const std::uint8_t> rest) {
  for (int tags = 0; (type == kEtherVlan || type == kEtherQinQ) && tags < 4; ++tags) {
    if (rest.size() < 4) return {FrameKind::Truncated, {}};
    type = be16(&rest[2]);
    rest = rest.subspan(4);
  }
  if (type != kEtherIpv4) return {};
  return parseIpv4(rest);
}

}  // namespace

LinkFrame parseLinkFrame(int link_type, std::span<const std::uint8_t> frame) {
  switch (link_type) {
    case kLinkEthernet:
      if (frame.size() < 14) return {FrameKind::Truncated, {}};
      return parseEtherType(be16(&frame[12]), frame.subspan(14));
    case kLinkSll:  // 16-byte header, protocol at 14
      if (frame.size() < 16) return {FrameKind::Truncated, {}};
      return parseEtherType(be16(&frame[14]), frame.subspan(16));
    case kLinkSll2:  // 20-byte header, protocol at 0
      if (frame.size() < 20) return {FrameKind::Truncated, {}};
      return parseEtherType(be16(&frame[0]), frame.subspan(20));
    case kLinkRaw:
    case kLinkRawOpenBsd:
    case kLinkIpv4:
      return parseIpv4(frame);
    case kLinkNull: {  // 4-byte address family in host order of the capturing machine; 2 = AF_INET
      if (frame.size() < 4) return {FrameKind::Truncated, {}};
      const bool inet = (frame[0] == 2 && frame[3] == 0) || (frame[3] == 2 && frame[0] == 0);
      return inet ? parseIpv4(frame.subspan(4)) : LinkFrame{};
    }
    default:
      return {FrameKind::UnsupportedLink, {}};
  }
}

}  // namespace ogf::driver_sources
