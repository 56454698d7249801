// A simulated capture read back with a minimal pcap reader written here (independent of the writer):
// classic header, Ethernet/IPv4/UDP framing with valid checksums, packet period, TOH = capture clock
// (across an hour boundary), position packets every 14 data packets.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "ogf/sim/capture_writer.hpp"
#include "ogf/sim/nmea.hpp"
#include "sim_test_world.hpp"
#include "sim_test_paths.hpp"

namespace ogf::sim {
namespace {

struct Frame {
  std::int64_t utime = 0;
  std::vector<std::uint8_t> bytes;
};

std::uint32_t le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] << 8 | p[1]); }

// One's-complement sum of big-endian 16-bit words, folded.
std::uint32_t onesSum(const std::uint8_t* p, std::size_t n, std::uint32_t sum = 0) {
  for (std::size_t i = 0; i + 1 < n; i += 2) sum += be16(p + i);
  if (n % 2) sum += static_cast<std::uint32_t>(p[n - 1] << 8);
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  return sum;
}

std::vector<Frame> readPcap(const std::string& path, std::array<std::uint8_t, 24>& header) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<Frame> frames;
  if (all.size() < 24) return frames;
  std::copy(all.begin(), all.begin() + 24, header.begin());
  std::size_t at = 24;
  while (at + 16 <= all.size()) {
    const std::uint32_t sec = le32(&all[at]);
    const std::uint32_t usec = le32(&all[at + 4]);
    const std::uint32_t incl = le32(&all[at + 8]);
    const std::uint32_t orig = le32(&all[at + 12]);
    EXPECT_EQ(incl, orig);
    EXPECT_LT(usec, 1000000u);
    at += 16;
    if (at + incl > all.size()) {
      ADD_FAILURE() << "truncated record";
      break;
    }
    frames.push_back(Frame{static_cast<std::int64_t>(sec) * 1000000 + usec,
                           std::vector<std::uint8_t>(all.begin() + static_cast<std::ptrdiff_t>(at),
                                                     all.begin() + static_cast<std::ptrdiff_t>(at + incl))});
    at += incl;
  }
  EXPECT_EQ(at, all.size()) << "bytes after the last record";
  return frames;
}

TEST(SimPcapCapture, FramesParseWithValidChecksumsAndTohOnTheCaptureClock) {
  const World world = test::groundOnly();
  const auto traj = Trajectory::build(TrajectorySpec{{{0, 0, 0}, {3, 0, 0}}, 1.0, false, 0.0});
  ASSERT_TRUE(traj.ok());
  // Start 0.1 s before 13:00:00 UTC so the TOH counter wraps inside the capture.
  const std::int64_t start = (1704110400LL + 3600) * 1000000 - 100000;
  const LidarSimulator sim(world, Eigen::Isometry3d(Eigen::Translation3d(0, 0, 1)), *traj, SensorConfig{}, start);
  const std::string path = test::scratchPath("capture.pcap").string();
  const auto summary = writeCapture(sim, 0.25, path);
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_EQ(summary->data_packets, 189u);  // ceil(0.25 s / 1327.104 µs)
  EXPECT_EQ(summary->position_packets, 189u / 14);

  std::array<std::uint8_t, 24> header{};
  const auto frames = readPcap(path, header);
  ASSERT_EQ(frames.size(), summary->data_packets + summary->position_packets);
  EXPECT_EQ(le32(&header[0]), 0xA1B2C3D4u);  // microsecond pcap, little-endian file
  EXPECT_EQ(header[4] | header[5] << 8, 2);
  EXPECT_EQ(header[6] | header[7] << 8, 4);
  EXPECT_EQ(le32(&header[16]), 65535u);
  EXPECT_EQ(le32(&header[20]), 1u);  // Ethernet

  std::size_t data = 0;
  std::size_t since_position = 0;
  std::int64_t previous = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const auto& f = frames[i].bytes;
    ASSERT_GE(f.size(), 42u);
    // Ethernet: broadcast, EtherType IPv4.
    for (int b = 0; b < 6; ++b) EXPECT_EQ(f[static_cast<std::size_t>(b)], 0xFF);
    EXPECT_EQ(be16(&f[12]), 0x0800);
    // IPv4: version/IHL, total length, UDP, checksum verifies (the folded sum is 0xFFFF), addresses.
    const std::uint8_t* ip = &f[14];
    EXPECT_EQ(ip[0], 0x45);
    EXPECT_EQ(be16(ip + 2), f.size() - 14);
    EXPECT_EQ(ip[9], 17);
    EXPECT_EQ(onesSum(ip, 20), 0xFFFFu) << "IPv4 header checksum, frame " << i;
    EXPECT_EQ((std::array<std::uint8_t, 4>{ip[12], ip[13], ip[14], ip[15]}), (std::array<std::uint8_t, 4>{192, 168, 1, 201}));
    EXPECT_EQ((std::array<std::uint8_t, 4>{ip[16], ip[17], ip[18], ip[19]}), (std::array<std::uint8_t, 4>{255, 255, 255, 255}));
    // UDP: length, checksum over the pseudo-header verifies.
    const std::uint8_t* udp = &f[34];
    const std::uint16_t port = be16(udp + 2);
    const std::size_t payload_size = f.size() - 42;
    EXPECT_EQ(be16(udp + 4), payload_size + 8);
    std::uint32_t pseudo = onesSum(ip + 12, 8) + 17 + be16(udp + 4);
    EXPECT_EQ(onesSum(udp, payload_size + 8, pseudo), 0xFFFFu) << "UDP checksum, frame " << i;
    const std::uint8_t* payload = &f[42];
    // Frames in time order; each payload's TOH is its pcap stamp's µs within the hour.
    EXPECT_GE(frames[i].utime, previous);
    previous = frames[i].utime;
    const std::uint32_t toh = port == 2368 ? le32(payload + 1200) : le32(payload + 198);
    EXPECT_EQ(toh, static_cast<std::uint32_t>(frames[i].utime % 3600000000LL)) << "frame " << i;
    if (port == 2368) {
      ASSERT_EQ(payload_size, 1206u);
      EXPECT_EQ(frames[i].utime, start + static_cast<std::int64_t>(std::floor(static_cast<double>(data) * 1327.104 + 1e-9)));
      ++data;
      ++since_position;
    } else {
      ASSERT_EQ(port, 8308);
      ASSERT_EQ(payload_size, 512u);
      EXPECT_EQ(since_position, 14u) << "position packet after " << since_position << " data packets";
      since_position = 0;
      EXPECT_EQ(payload[202], 2) << "PPS locked";
      const std::string nmea(reinterpret_cast<const char*>(payload + 206));
      ASSERT_EQ(nmea.rfind("$GPRMC,", 0), 0u) << nmea;
      const auto star = nmea.find('*');
      ASSERT_NE(star, std::string::npos);
      EXPECT_EQ(std::strtoul(nmea.substr(star + 1, 2).c_str(), nullptr, 16),
                nmeaChecksum(std::string_view(nmea).substr(1, star - 1)));
    }
  }
  EXPECT_EQ(data, summary->data_packets);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace ogf::sim
