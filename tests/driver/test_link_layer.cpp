// Link-layer parsing of captured frames: Ethernet, VLAN, Linux cooked capture, fragments, truncation.
#include <gtest/gtest.h>

#include <vector>

#include "ogf/driver_sources/link_layer.hpp"

namespace os = ogf::driver_sources;

namespace {

std::vector<std::uint8_t> ipv4Udp(std::uint16_t dst_port, std::size_t payload, std::uint16_t fragment = 0) {
  std::vector<std::uint8_t> ip(20 + 8 + payload, 0xAB);
  const std::size_t total = ip.size();
  ip[0] = 0x45;
  ip[2] = static_cast<std::uint8_t>(total >> 8), ip[3] = static_cast<std::uint8_t>(total);
  ip[6] = static_cast<std::uint8_t>(fragment >> 8), ip[7] = static_cast<std::uint8_t>(fragment);
  ip[9] = 17;
  ip[12] = 192, ip[13] = 168, ip[14] = 1, ip[15] = 201;
  ip[20] = 0x09, ip[21] = 0x40;  // source port 2368
  ip[22] = static_cast<std::uint8_t>(dst_port >> 8), ip[23] = static_cast<std::uint8_t>(dst_port);
  ip[24] = static_cast<std::uint8_t>((payload + 8) >> 8), ip[25] = static_cast<std::uint8_t>(payload + 8);
  return ip;
}

std::vector<std::uint8_t> withHeader(const std::vector<std::uint8_t>& header,
                                     const std::vector<std::uint8_t>& ip) {
  std::vector<std::uint8_t> frame;
  frame.reserve(header.size() + ip.size());
  for (std::uint8_t b : header) frame.push_back(b);
  for (std::uint8_t b : ip) frame.push_back(b);
  return frame;
}

std::vector<std::uint8_t> ethernet(std::initializer_list<std::uint8_t> after_macs) {
  std::vector<std::uint8_t> h;
  h.reserve(12 + after_macs.size());
  for (int i = 0; i < 12; ++i) h.push_back(0xFF);
  for (std::uint8_t b : after_macs) h.push_back(b);
  return h;
}

}  // namespace

TEST(LinkLayer, EthernetUdpDatagramIsFound) {
  const auto f = os::parseLinkFrame(1, withHeader(ethernet({0x08, 0x00}), ipv4Udp(2368, 1206)));
  ASSERT_EQ(f.kind, os::FrameKind::Udp);
  EXPECT_EQ(f.datagram.destination_port, 2368);
  EXPECT_EQ(f.datagram.payload.size(), 1206u);
  EXPECT_EQ(os::formatIpv4(f.datagram.source_ip), "192.168.1.201");
}

TEST(LinkLayer, VlanTagsAreSkipped) {
  const auto f = os::parseLinkFrame(
      1, withHeader(ethernet({0x88, 0xa8, 0, 5, 0x81, 0x00, 0, 7, 0x08, 0x00}), ipv4Udp(8308, 512)));
  ASSERT_EQ(f.kind, os::FrameKind::Udp);
  EXPECT_EQ(f.datagram.destination_port, 8308);
  EXPECT_EQ(f.datagram.payload.size(), 512u);
}

TEST(LinkLayer, LinuxCookedCaptureIsParsed) {
  std::vector<std::uint8_t> sll(16, 0);
  sll[14] = 0x08;
  const auto f = os::parseLinkFrame(113, withHeader(sll, ipv4Udp(2368, 1206)));
  ASSERT_EQ(f.kind, os::FrameKind::Udp);
  std::vector<std::uint8_t> sll2(20, 0);
  sll2[0] = 0x08;
  EXPECT_EQ(os::parseLinkFrame(276, withHeader(sll2, ipv4Udp(2368, 1206))).kind, os::FrameKind::Udp);
  EXPECT_EQ(os::parseLinkFrame(101, ipv4Udp(2368, 10)).kind, os::FrameKind::Udp);
}

TEST(LinkLayer, FragmentsTruncationAndOtherTrafficAreTold) {
  EXPECT_EQ(os::parseLinkFrame(1, withHeader(ethernet({0x08, 0x00}), ipv4Udp(2368, 1206, 0x2000))).kind,
            os::FrameKind::Fragment);
  auto cut = withHeader(ethernet({0x08, 0x00}), ipv4Udp(2368, 1206));
  cut.resize(100);
  EXPECT_EQ(os::parseLinkFrame(1, cut).kind, os::FrameKind::Truncated);
  EXPECT_EQ(os::parseLinkFrame(1, withHeader(ethernet({0x86, 0xdd}), ipv4Udp(2368, 10))).kind,
            os::FrameKind::NotUdp);
  EXPECT_EQ(os::parseLinkFrame(9999, ipv4Udp(2368, 10)).kind, os::FrameKind::UnsupportedLink);
  EXPECT_EQ(os::parseLinkFrame(1, {}).kind, os::FrameKind::Truncated);
}

TEST(LinkLayer, Ipv4AddressesFormatAndParse) {
  std::uint32_t ip = 0;
  ASSERT_TRUE(os::parseIpv4("192.168.1.201", ip));
  EXPECT_EQ(ip, 0xC0A801C9u);
  EXPECT_FALSE(os::parseIpv4("192.168.1", ip));
  EXPECT_FALSE(os::parseIpv4("192.168.1.300", ip));
  EXPECT_FALSE(os::parseIpv4("1.2.3.4x", ip));
}
