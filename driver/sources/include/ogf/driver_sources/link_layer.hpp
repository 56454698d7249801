// Finds the UDP datagram inside a captured frame: Ethernet (with 802.1Q/802.1ad VLAN tags), Linux cooked
// capture v1 and v2 (SLL), raw IPv4 and BSD loopback link types; IPv4 with options. IPv4 fragments are
// recognised and reported, not reassembled (a Velodyne datagram fits one 1500-byte frame).
#pragma once

#include <cstdint>
#include <span>

#include "ogf/driver_sources/udp_datagram.hpp"

namespace ogf::driver_sources {

enum class FrameKind : std::uint8_t {
  Udp,             // `datagram` is set
  NotUdp,          // ARP, IPv6, TCP, ...: not for us, not an error
  Fragment,        // an IPv4 fragment
  Truncated,       // headers or payload cut short (snaplen or a corrupt length)
  UnsupportedLink  // a link type this parser does not know
};

struct LinkFrame {
  FrameKind kind = FrameKind::NotUdp;
  UdpDatagram datagram;  // utime left 0: the caller sets it
};

// `link_type` is the pcap DLT/LINKTYPE value (1 Ethernet, 113 SLL, 276 SLL2, 101/12/228 raw IPv4,
// 0 BSD loopback).
LinkFrame parseLinkFrame(int link_type, std::span<const std::uint8_t> frame);

}  // namespace ogf::driver_sources
