// Writes a classic libpcap capture (microsecond stamps, linktype 1 = Ethernet) of UDP datagrams framed as
// the VLP-16 sends them: broadcast Ethernet from a Velodyne MAC, IPv4 192.168.1.201 → 255.255.255.255
// with a valid header checksum, UDP with a valid checksum, source port = destination port.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>

#include "ogf/common/result.hpp"

namespace ogf::sim {

inline constexpr std::size_t kEthernetHeaderBytes = 14;
inline constexpr std::size_t kIpv4HeaderBytes = 20;
inline constexpr std::size_t kUdpHeaderBytes = 8;
inline constexpr std::size_t kFrameHeaderBytes = kEthernetHeaderBytes + kIpv4HeaderBytes + kUdpHeaderBytes;

// The Internet checksum (RFC 1071) of `bytes`: the one's complement of the one's-complement sum of the
// 16-bit big-endian words. Over an IPv4 header whose checksum field is filled in, the sum is 0.
std::uint16_t internetChecksum(std::span<const std::uint8_t> bytes, std::uint32_t initial_sum = 0);

struct UdpEndpoints {
  std::array<std::uint8_t, 6> source_mac{0x60, 0x76, 0x88, 0x00, 0x00, 0x01};  // Velodyne OUI 60:76:88
  std::array<std::uint8_t, 4> source_ip{192, 168, 1, 201};                      // factory default
  std::array<std::uint8_t, 4> destination_ip{255, 255, 255, 255};               // broadcast
};

class PcapWriter {
 public:
  static Result<PcapWriter> open(const std::string& path, UdpEndpoints endpoints = {});

  // One Ethernet/IPv4/UDP frame carrying `payload` to `port`, stamped `utime` (µs since the epoch).
  Status writeUdp(std::int64_t utime, std::uint16_t port, std::span<const std::uint8_t> payload);

  // Flushes and closes; reports a write error that happened on the way.
  Status close();

  std::uint64_t framesWritten() const { return frames_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, FileCloser> file_;
  std::string path_;
  UdpEndpoints endpoints_;
  std::uint16_t ip_id_ = 0;
  std::uint64_t frames_ = 0;
  std::array<std::uint8_t, kFrameHeaderBytes + 1500> frame_{};
};

}  // namespace ogf::sim
