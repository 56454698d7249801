// The classic pcap format: a 24-byte global header (magic 0xA1B2C3D4 written in host order, version
// 2.4, snaplen, linktype) and per frame a 16-byte record header (seconds, microseconds, captured length,
// original length). Written little-endian explicitly, the order readers detect from the magic.
#include "ogf/sim/pcap_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "ogf/sim/byte_writer.hpp"

namespace ogf::sim {
namespace {

constexpr std::uint32_t kPcapMagicMicroseconds = 0xA1B2C3D4;
constexpr std::uint32_t kSnapLength = 65535;
constexpr std::uint32_t kLinkTypeEthernet = 1;
constexpr std::uint8_t kIpProtocolUdp = 17;
constexpr std::uint8_t kTimeToLive = 64;

}  // namespace

std::uint16_t internetChecksum(std::span<const std::uint8_t> bytes, std::uint32_t initial_sum) {
  std::uint64_t sum = initial_sum;
  std::size_t i = 0;
  for (; i + 1 < bytes.size(); i += 2) sum += static_cast<std::uint32_t>(bytes[i] << 8 | bytes[i + 1]);
  if (i < bytes.size()) sum += static_cast<std::uint32_t>(bytes[i] << 8);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return static_cast<std::uint16_t>(~sum & 0xFFFF);
}

Result<PcapWriter> PcapWriter::open(const std::string& path, UdpEndpoints endpoints) {
  PcapWriter w;
  w.path_ = path;
  w.endpoints_ = endpoints;
  w.file_.reset(std::fopen(path.c_str(), "wb"));
  if (!w.file_) return Error{path + ": cannot create: " + std::strerror(errno)};
  std::array<std::uint8_t, 24> header{};
  putLe32(header, 0, kPcapMagicMicroseconds);
  putLe16(header, 4, 2);  // version 2.4
  putLe16(header, 6, 4);
  // thiszone and sigfigs stay 0
  putLe32(header, 16, kSnapLength);
  putLe32(header, 20, kLinkTypeEthernet);
  if (std::fwrite(header.data(), 1, header.size(), w.file_.get()) != header.size()) {
    return Error{path + ": cannot write the pcap header"};
  }
  return w;
}

Status PcapWriter::writeUdp(std::int64_t utime, std::uint16_t port, std::span<const std::uint8_t> payload) {
  if (!file_) return Error{path_ + ": not open"};
  if (payload.size() > frame_.size() - kFrameHeaderBytes) return Error{path_ + ": UDP payload too large"};
  std::span<std::uint8_t> f(frame_);
  // Ethernet II: broadcast destination, Velodyne source, EtherType IPv4.
  std::fill_n(f.begin(), 6, std::uint8_t{0xFF});
  std::copy(endpoints_.source_mac.begin(), endpoints_.source_mac.end(), f.begin() + 6);
  putBe16(f, 12, 0x0800);
  // IPv4 header, no options.
  const std::size_t ip = kEthernetHeaderBytes;
  const auto ip_length = static_cast<std::uint16_t>(kIpv4HeaderBytes + kUdpHeaderBytes + payload.size());
  f[ip] = 0x45;  // version 4, 5 words
  f[ip + 1] = 0;
  putBe16(f, ip + 2, ip_length);
  putBe16(f, ip + 4, ip_id_++);
  putBe16(f, ip + 6, 0x4000);  // don't fragment
  f[ip + 8] = kTimeToLive;
  f[ip + 9] = kIpProtocolUdp;
  putBe16(f, ip + 10, 0);
  std::copy(endpoints_.source_ip.begin(), endpoints_.source_ip.end(), f.begin() + ip + 12);
  std::copy(endpoints_.destination_ip.begin(), endpoints_.destination_ip.end(), f.begin() + ip + 16);
  putBe16(f, ip + 10, internetChecksum(f.subspan(ip, kIpv4HeaderBytes)));
  // UDP header, then the payload; the checksum covers the pseudo-header (addresses, protocol, length).
  const std::size_t udp = ip + kIpv4HeaderBytes;
  const auto udp_length = static_cast<std::uint16_t>(kUdpHeaderBytes + payload.size());
  putBe16(f, udp, port);
  putBe16(f, udp + 2, port);
  putBe16(f, udp + 4, udp_length);
  putBe16(f, udp + 6, 0);
  std::copy(payload.begin(), payload.end(), f.begin() + static_cast<std::ptrdiff_t>(kFrameHeaderBytes));
  std::uint32_t pseudo = 0;
  for (std::size_t i = 0; i < 8; i += 2) pseudo += static_cast<std::uint32_t>(f[ip + 12 + i] << 8 | f[ip + 13 + i]);
  pseudo += kIpProtocolUdp + udp_length;
  std::uint16_t udp_sum = internetChecksum(f.subspan(udp, udp_length), pseudo);
  if (udp_sum == 0) udp_sum = 0xFFFF;  // 0 means "no checksum" in UDP over IPv4
  putBe16(f, udp + 6, udp_sum);

  const std::size_t frame_length = kFrameHeaderBytes + payload.size();
  std::array<std::uint8_t, 16> record{};
  const std::int64_t sec = utime >= 0 ? utime / 1000000 : (utime - 999999) / 1000000;
  putLe32(record, 0, static_cast<std::uint32_t>(sec));
  putLe32(record, 4, static_cast<std::uint32_t>(utime - sec * 1000000));
  putLe32(record, 8, static_cast<std::uint32_t>(frame_length));
  putLe32(record, 12, static_cast<std::uint32_t>(frame_length));
  if (std::fwrite(record.data(), 1, record.size(), file_.get()) != record.size() ||
      std::fwrite(frame_.data(), 1, frame_length, file_.get()) != frame_length) {
    return Error{path_ + ": write failed at frame " + std::to_string(frames_) + ": " + std::strerror(errno)};
  }
  ++frames_;
  return Ok{};
}

Status PcapWriter::close() {
  if (!file_) return Ok{};
  const bool flushed = std::fflush(file_.get()) == 0 && !std::ferror(file_.get());
  file_.reset();
  if (!flushed) return Error{path_ + ": write failed: " + std::strerror(errno)};
  return Ok{};
}

}  // namespace ogf::sim
