// The capture reader: pcapng as well as pcap, Linux cooked captures and VLAN tags in a real file, a record
// cut short, and files that are not captures.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "capture_decoding.hpp"
#include "ogf/driver_sources/pcap_file_reader.hpp"
#include "support/shared_data.hpp"

namespace os = ogf::driver_sources;

namespace {

void put16(std::vector<std::uint8_t>& v, std::size_t at, std::uint16_t x) {
  v[at] = static_cast<std::uint8_t>(x >> 8);
  v[at + 1] = static_cast<std::uint8_t>(x);
}

// A UDP/IPv4 packet to `port` with `payload` bytes of 0x5A.
std::vector<std::uint8_t> ipv4Udp(std::uint16_t port, std::size_t payload) {
  std::vector<std::uint8_t> ip(28 + payload, 0x5A);
  ip[0] = 0x45;
  put16(ip, 2, static_cast<std::uint16_t>(ip.size()));
  put16(ip, 6, 0);
  ip[9] = 17;
  ip[12] = 192, ip[13] = 168, ip[14] = 1, ip[15] = 201;
  put16(ip, 20, 2368);
  put16(ip, 22, port);
  put16(ip, 24, static_cast<std::uint16_t>(payload + 8));
  return ip;
}

// A classic little-endian pcap with `link_type` holding `frames`; the last record's data may be cut.
std::vector<std::uint8_t> pcapFile(std::uint32_t link_type,
                                   const std::vector<std::vector<std::uint8_t>>& frames,
                                   std::size_t cut_last_by = 0) {
  std::vector<std::uint8_t> f;
  auto le32 = [&f](std::uint32_t x) {
    for (int i = 0; i < 4; ++i) f.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
  };
  le32(0xa1b2c3d4);
  f.push_back(2), f.push_back(0), f.push_back(4), f.push_back(0);
  le32(0), le32(0), le32(65535), le32(link_type);
  std::uint32_t usec = 0;
  for (const auto& frame : frames) {
    le32(1600000000), le32(usec += 1327), le32(static_cast<std::uint32_t>(frame.size())),
        le32(static_cast<std::uint32_t>(frame.size()));
    f.insert(f.end(), frame.begin(), frame.end());
  }
  if (cut_last_by > 0 && cut_last_by < f.size())
    f.erase(f.end() - static_cast<std::ptrdiff_t>(cut_last_by), f.end());
  return f;
}

std::unique_ptr<os::PcapFileReader> openMemory(std::vector<std::uint8_t>& bytes) {
  std::FILE* file = ::fmemopen(bytes.data(), bytes.size(), "rb");
  auto reader = os::PcapFileReader::open(file, "memory.pcap");
  EXPECT_TRUE(reader) << reader.error().message;
  return reader ? std::move(*reader) : nullptr;
}

}  // namespace

TEST(PcapReader, LinuxCookedCaptureWithVlanTagsYieldsTheDatagrams) {
  std::vector<std::uint8_t> sll(16, 0);
  sll[14] = 0x81, sll[15] = 0x00;  // 802.1Q, then IPv4
  const std::vector<std::uint8_t> tag{0x00, 0x05, 0x08, 0x00};
  std::vector<std::vector<std::uint8_t>> frames;
  for (const std::uint16_t port : std::initializer_list<std::uint16_t>{2368, 8308, 2368}) {
    auto frame = sll;
    frame.insert(frame.end(), tag.begin(), tag.end());
    const auto ip = ipv4Udp(port, port == 2368 ? 1206 : 512);
    frame.insert(frame.end(), ip.begin(), ip.end());
    frames.push_back(frame);
  }
  auto bytes = pcapFile(113, frames);
  auto reader = openMemory(bytes);
  ASSERT_TRUE(reader);
  EXPECT_EQ(reader->linkType(), 113);
  os::PcapRecord r;
  std::vector<std::uint16_t> ports;
  while (reader->next(r) == os::ReadStatus::Datagram) {
    ports.push_back(r.datagram.destination_port);
    EXPECT_EQ(r.datagram.payload.size(), r.datagram.destination_port == 2368 ? 1206u : 512u);
  }
  EXPECT_EQ(ports, (std::vector<std::uint16_t>{2368, 8308, 2368}));
  EXPECT_EQ(reader->error(), "");
}

TEST(PcapReader, RecordCutShortStopsWithAMessageAfterTheRecordsBeforeIt) {
  std::vector<std::uint8_t> eth(12, 0xFF);
  eth.push_back(0x08), eth.push_back(0x00);
  std::vector<std::vector<std::uint8_t>> frames;
  for (int i = 0; i < 3; ++i) {
    auto frame = eth;
    const auto ip = ipv4Udp(2368, 1206);
    frame.insert(frame.end(), ip.begin(), ip.end());
    frames.push_back(frame);
  }
  auto bytes = pcapFile(1, frames, 500);
  auto reader = openMemory(bytes);
  ASSERT_TRUE(reader);
  os::PcapRecord r;
  int datagrams = 0;
  os::ReadStatus s;
  while ((s = reader->next(r)) == os::ReadStatus::Datagram) ++datagrams;
  EXPECT_EQ(s, os::ReadStatus::Error);
  EXPECT_EQ(datagrams, 2);
  EXPECT_NE(reader->error().find("record 2"), std::string::npos) << reader->error();
  EXPECT_EQ(reader->next(r), os::ReadStatus::Error);  // stays failed
}

TEST(PcapReader, NotACaptureIsRefusedWithTheName) {
  std::vector<std::uint8_t> text(100, 'x');
  std::FILE* file = ::fmemopen(text.data(), text.size(), "rb");
  const auto reader = os::PcapFileReader::open(file, "notes.txt");
  ASSERT_FALSE(reader);
  EXPECT_NE(reader.error().message.find("notes.txt"), std::string::npos);
}

TEST(PcapReader, PcapngDecodesToTheSameScansAsPcap) {
  OGF_REQUIRE_SHARED_FILE(pcap, "data/real/monterey-first-100-packets.pcap");
  if (std::system("command -v editcap >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "editcap (wireshark-common) absent";
  const std::string pcapng =
      (std::filesystem::temp_directory_path() / ("ogf-" + std::to_string(::getpid()) + ".pcapng")).string();
  ASSERT_EQ(std::system(("editcap -F pcapng '" + pcap.string() + "' '" + pcapng + "'").c_str()), 0);
  const auto a = ogf::testing::decodeCapture(pcap);
  const auto b = ogf::testing::decodeCapture(pcapng);
  std::filesystem::remove(pcapng);
  EXPECT_EQ(b.read_error, "");
  ASSERT_EQ(a.scans.size(), b.scans.size());
  EXPECT_EQ(a.counters.data_packets, b.counters.data_packets);
  EXPECT_EQ(a.counters.position_packets, b.counters.position_packets);
  for (std::size_t i = 0; i < a.scans.size(); ++i)
    EXPECT_EQ(a.scans[i].points.size(), b.scans[i].points.size());
}
