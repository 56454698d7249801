// Bad input at ogf-driver as a real process on UDP over loopback: a real capture (VeloView's VLP-16
// test capture) is sent to the data and position ports, and after the first packets every kind of bad
// datagram is mixed into it: random bytes of random sizes, empty, truncated and oversized datagrams,
// wrong-size position packets, data packets with a bad block flag in each block or an azimuth beyond
// 36000, random 1206-byte payloads, data packets whose timestamp is past the hour or whose return-mode or
// product byte is unknown, position packets with a bad PPS byte, a timestamp past the hour, garbage NMEA,
// a forged GPS fix dated 2099 (checksum right, PPS locked) or random bytes, and valid packets from another
// host. Checked: each is counted in VELODYNE_STATUS (bad_size, bad_block_flag, bad_other, foreign_sender,
// bad_time_of_hour, unknown_return_mode, unknown_model, bad_position, nmea_time_refused), the driver keeps
// running, and the scans it publishes are exactly those the driver library decodes from the capture alone,
// on the host's hour.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>
#include <ogf/driver_status_t.hpp>
#include <ogf/lidar_scan_t.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <thread>

#include "capture_decoding.hpp"
#include "ogf/velodyne/position_packet.hpp"
#include "ogf/velodyne/wire_format.hpp"
#include "support/daemon_process.hpp"
#include "support/message_log.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using Driver = ogf::testing::DaemonProcess<ogf::driver_status_t>;
using Bytes = std::vector<std::uint8_t>;

constexpr const char* kCapture = "data/real/vlp-16-test-90deg-1-50-frames.pcap";
constexpr std::int64_t kCleanStart = 300;  // valid data packets before any bad one: the model is decided

// A UDP socket bound to `address` (127.0.0.1 is the sensor, 127.0.0.2 another host on its LAN).
class Sender {
 public:
  explicit Sender(std::uint32_t address) : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {
    sockaddr_in from{};
    from.sin_family = AF_INET;
    from.sin_addr.s_addr = htonl(address);
    bound_ = fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&from), sizeof(from)) == 0;
  }
  ~Sender() {
    if (fd_ >= 0) ::close(fd_);
  }
  Sender(const Sender&) = delete;
  Sender& operator=(const Sender&) = delete;
  bool ok() const { return bound_; }
  void send(int port, const Bytes& payload) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(port));
    to.sin_addr.s_addr = htonl(0x7F000001);
    ::sendto(fd_, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
  }

 private:
  int fd_;
  bool bound_ = false;
};

// What the driver must count: the capture's own packets plus every bad datagram sent.
struct Expected {
  std::int64_t extra_position = 0, bad_size = 0, bad_block_flag = 0, bad_other = 0, foreign = 0;
  std::int64_t bad_time_of_hour = 0, unknown_return_mode = 0, unknown_model = 0, bad_position = 0, nmea_refused = 0;
};

Bytes randomBytes(std::mt19937& rng, std::size_t n) {
  std::uniform_int_distribution<int> byte(0, 255);
  Bytes b(n);
  for (auto& x : b) x = static_cast<std::uint8_t>(byte(rng));
  return b;
}

// What the driver must count before any bad datagram: what the capture itself holds that is rejected.
Expected rejectedInTheCapture(const ogf::velodyne::StreamCounters& c) {
  Expected want;
  want.bad_size = c.bad_size;
  want.bad_block_flag = c.bad_block_flag;
  want.bad_other = c.bad_other;
  want.bad_time_of_hour = c.bad_time_of_hour;
  want.unknown_return_mode = c.unknown_return_mode;
  want.unknown_model = c.unknown_model;
  want.bad_position = c.bad_position;
  return want;
}

// Every kind of bad datagram, sent beside a valid one (which each kind is made from) and added to what the
// driver must count.
class BadDatagrams {
 public:
  BadDatagrams(int data_port, int position_port, Expected& want)
      : data_port_(data_port), position_port_(position_port), want_(want) {}
  bool ok() const { return sensor_.ok() && other_host_.ok(); }

  // The data port: wrong sizes, bad block flags, an azimuth beyond 36000, a timestamp past the hour, unknown
  // return mode and product bytes, and a valid packet from another host.
  void sendBadData(const Bytes& valid) {
    sendWrongSizes();
    Bytes random1206 = randomBytes(rng_, ogf::velodyne::wire::kDataPacketSize);
    random1206[0] = 0x00;  // never the 0xEEFF flag by chance
    sensor_.send(data_port_, random1206);
    ++want_.bad_block_flag;
    for (int block = 0; block < 12; ++block) {
      Bytes flagged = valid;
      flagged[static_cast<std::size_t>(100 * block)] = 0xFF;  // 0xDDFF: the lower bank of an HDL-64E
      flagged[static_cast<std::size_t>(100 * block + 1)] = 0xDD;
      sensor_.send(data_port_, flagged);
      ++want_.bad_block_flag;
    }
    Bytes azimuth = valid;
    azimuth[3 * 100 + 2] = 0xA1;  // block 3's azimuth 36001 (0x8CA1)
    azimuth[3 * 100 + 3] = 0x8C;
    sensor_.send(data_port_, azimuth);
    ++want_.bad_other;
    Bytes past_hour = valid;
    for (int i = 1200; i < 1204; ++i) past_hour[static_cast<std::size_t>(i)] = 0xFF;  // 4294 s past the hour
    sensor_.send(data_port_, past_hour);
    ++want_.bad_time_of_hour;
    Bytes mode = valid;
    mode[1204] = 0x99;
    sensor_.send(data_port_, mode);
    ++want_.unknown_return_mode;
    Bytes product = valid;
    product[1205] = 0x77;
    sensor_.send(data_port_, product);
    ++want_.unknown_model;
    other_host_.send(data_port_, valid);
    ++want_.foreign;
  }

  // The position port: wrong sizes, a bad PPS byte, a timestamp past the hour, a forged fix dated 2099,
  // random 512-byte packets, garbage NMEA, and a valid packet from another host.
  void sendBadPosition(const Bytes& valid) {
    for (std::size_t n : {std::size_t{0}, std::size_t{511}, std::size_t{513}, std::size_t{1206}}) {
      sensor_.send(position_port_, randomBytes(rng_, n));
      ++want_.bad_size;
    }
    Bytes pps = valid;
    pps[202] = 9;  // PPS status beyond 3
    sensor_.send(position_port_, pps);
    ++want_.bad_position;
    Bytes past_hour = valid;
    for (int i = 198; i < 202; ++i) past_hour[static_cast<std::size_t>(i)] = 0xFF;
    sensor_.send(position_port_, past_hour);
    ++want_.bad_time_of_hour;
    sensor_.send(position_port_, forgedFix2099(valid));
    ++want_.extra_position;
    ++want_.nmea_refused;
    sendRandomPositionPackets();
    // Garbage NMEA is not an error (the packet's timestamp and PPS state stand; the sentence gives no fix).
    Bytes nmea = valid;
    const Bytes garbage = randomBytes(rng_, 306);
    std::copy(garbage.begin(), garbage.end(), nmea.begin() + 206);
    nmea[206] = '$';
    sensor_.send(position_port_, nmea);
    ++want_.extra_position;
    Bytes sentence = valid;
    const std::string fake = "$GPRMC,999999,Q,not,a,fix*00\r\n";
    std::copy(fake.begin(), fake.end(), sentence.begin() + 206);
    sensor_.send(position_port_, sentence);
    ++want_.extra_position;
    other_host_.send(position_port_, valid);
    ++want_.foreign;
  }

  // The capture's own packets from the sensor's address.
  void sendValid(int port, const Bytes& payload) const { sensor_.send(port, payload); }

 private:
  // Sizes that are neither a data (1206) nor a position (512) packet: truncated, oversized, empty.
  void sendWrongSizes() {
    const std::vector<std::size_t> wrong_sizes = {0, 1, 100, 511, 513, 1205, 1207, 1248, 1500, 9000, 65000};
    for (std::size_t n : wrong_sizes) {
      sensor_.send(data_port_, randomBytes(rng_, n));
      ++want_.bad_size;
    }
    std::uniform_int_distribution<std::size_t> any_size(0, 2000);
    for (int i = 0; i < 20; ++i) {
      std::size_t n = any_size(rng_);
      if (n == ogf::velodyne::wire::kDataPacketSize) ++n;
      sensor_.send(data_port_, randomBytes(rng_, n));
      ++want_.bad_size;
    }
  }
  // A forged fix: PPS locked, a well-formed sentence with its checksum right, dated 2099.
  static Bytes forgedFix2099(const Bytes& valid) {
    Bytes forged = valid;
    std::fill(forged.begin() + 206, forged.end(), 0);
    forged[202] = 2;
    const std::string body = "GPRMC,120000,A,3707.8178,N,12139.2690,W,010.3,188.2,010199,013.8,E,D";
    unsigned x = 0;
    for (char c : body) x ^= static_cast<unsigned char>(c);
    char sum[8];
    std::snprintf(sum, sizeof(sum), "*%02X\r\n", x);
    const std::string sentence2099 = "$" + body + sum;
    std::copy(sentence2099.begin(), sentence2099.end(), forged.begin() + 206);
    return forged;
  }
  // Random 512-byte packets: refused by their timestamp or their structure, never taken as position packets.
  void sendRandomPositionPackets() {
    for (int i = 0; i < 5; ++i) {
      const Bytes r = randomBytes(rng_, ogf::velodyne::wire::kPositionPacketSize);
      sensor_.send(position_port_, r);
      const std::uint32_t toh = ogf::velodyne::wire::readLe32(r.data() + 198);
      if (toh >= ogf::velodyne::wire::kMicrosecondsPerHour) {
        ++want_.bad_time_of_hour;
      } else if (ogf::velodyne::parsePositionPacket(r)) {
        ++want_.extra_position;
      } else {
        ++want_.bad_position;
      }
    }
  }

  int data_port_, position_port_;
  Expected& want_;
  const Sender sensor_{0x7F000001}, other_host_{0x7F000002};
  std::mt19937 rng_{7};
};

// Sends the capture to the driver at about the sensor's own rate, mixing bad datagrams in after the first
// kCleanStart data packets; returns how many data packets of the capture were sent.
std::int64_t sendCaptureWithBadDatagrams(const fs::path& capture, int data_port, int position_port,
                                         BadDatagrams& bad) {
  auto reader = ogf::driver_sources::PcapFileReader::open(capture);
  EXPECT_TRUE(reader);
  if (!reader) return 0;
  std::int64_t data_sent = 0, position_sent = 0;
  ogf::driver_sources::PcapRecord record;
  while ((*reader)->next(record) != ogf::driver_sources::ReadStatus::End && (*reader)->error().empty()) {
    if (record.kind != ogf::driver_sources::FrameKind::Udp) continue;
    const auto& d = record.datagram;
    const Bytes payload(d.payload.begin(), d.payload.end());
    if (d.destination_port == 2368) {
      bad.sendValid(data_port, payload);
      ++data_sent;
      if (data_sent > kCleanStart && data_sent % 100 == 0) bad.sendBadData(payload);
    } else if (d.destination_port == 8308) {
      bad.sendValid(position_port, payload);
      ++position_sent;
      if (data_sent > kCleanStart && position_sent % 20 == 0) bad.sendBadPosition(payload);
    }
    std::this_thread::sleep_for(300us);  // about the sensor's own rate
  }
  return data_sent;
}

// The driver's status reaches every count in `want`; else what it says against what was expected.
::testing::AssertionResult countedInStatus(const Driver& driver, const Expected& want, std::int64_t want_data,
                                           std::int64_t want_position) {
  const auto counted = driver.waitForStatus(
      [&](const ogf::driver_status_t& s) {
        return s.data_packets == want_data && s.position_packets == want_position && s.bad_size == want.bad_size &&
               s.bad_block_flag == want.bad_block_flag && s.bad_other == want.bad_other &&
               s.foreign_sender == want.foreign && s.bad_time_of_hour == want.bad_time_of_hour &&
               s.unknown_return_mode == want.unknown_return_mode && s.unknown_model == want.unknown_model &&
               s.bad_position == want.bad_position && s.nmea_time_refused == want.nmea_refused;
      },
      20s);
  if (counted) return ::testing::AssertionSuccess();
  const auto s = driver.latestStatus();
  if (!s) return ::testing::AssertionFailure() << "no status";
  return ::testing::AssertionFailure()
         << "status: data " << s->data_packets << "/" << want_data << ", position " << s->position_packets << "/"
         << want_position << ", bad_size " << s->bad_size << "/" << want.bad_size << ", bad_block_flag "
         << s->bad_block_flag << "/" << want.bad_block_flag << ", bad_other " << s->bad_other << "/"
         << want.bad_other << ", foreign_sender " << s->foreign_sender << "/" << want.foreign
         << ", bad_time_of_hour " << s->bad_time_of_hour << "/" << want.bad_time_of_hour
         << ", unknown_return_mode " << s->unknown_return_mode << "/" << want.unknown_return_mode
         << ", unknown_model " << s->unknown_model << "/" << want.unknown_model << ", bad_position "
         << s->bad_position << "/" << want.bad_position << ", nmea_time_refused " << s->nmea_time_refused << "/"
         << want.nmea_refused;
}

// The published scans are those the library decodes from the capture alone, on the host's hour; returns
// their points.
std::int64_t expectTheCleanDecode(const std::vector<ogf::lidar_scan_t>& got,
                                  const std::vector<ogf::velodyne::Scan>& expected) {
  EXPECT_EQ(got.size(), expected.size());
  if (got.size() != expected.size()) return 0;
  std::int64_t points = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const auto& e = expected[i];
    EXPECT_EQ(static_cast<std::size_t>(got[i].num_points), e.points.size()) << "scan " << i;
    if (static_cast<std::size_t>(got[i].num_points) != e.points.size()) return points;
    EXPECT_EQ(got[i].packets_received, e.packets_received) << "scan " << i;
    for (std::size_t p = 0; p < e.points.size(); p += 101) {
      EXPECT_EQ(got[i].x[p], e.points[p].x);
      EXPECT_EQ(got[i].time_offset_ns[p], e.points[p].time_offset_ns);
    }
    points += got[i].num_points;
    // No scan took the forged date: device time stays within the hour rule of the host clock.
    EXPECT_LT(std::llabs(got[i].device_utime_start - got[i].host_utime_start), 3'600'000'000LL) << "scan " << i;
  }
  return points;
}

TEST(DriverBadInput, EveryBadDatagramIsCountedAndTheValidScansStillComeOut) {
  OGF_REQUIRE_SHARED_FILE(capture, kCapture);
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(52);
  ogf::testing::MessageLog<ogf::lidar_scan_t> scans(url, "BAD_SCAN");  // in the order published
  const int data_port = 30000 + static_cast<int>(::getpid() % 20000) + 52;
  const int position_port = data_port + 1000;
  const fs::path log = fs::temp_directory_path() / ("ogf-badinput-driver-" + std::to_string(::getpid()) + ".log");
  Driver driver({OGF_BIN_DIR "/ogf-driver", "--bind-address", "127.0.0.1", "--data-port", std::to_string(data_port),
                 "--position-port", std::to_string(position_port), "--sensor-ip", "127.0.0.1", "--lcm-url", url,
                 "--scan-channel", "BAD_SCAN", "--status-channel", "BAD_STATUS", "--no-packets", "--log-level",
                 "warn"},
                log.string(), url, "BAD_STATUS");
  ASSERT_TRUE(driver.reportsStatus(15s));

  // The library on the capture alone, configured as the driver's defaults: the scans to expect, and what the
  // capture itself holds that is rejected (counted before any bad datagram is added).
  const auto expected = ogf::testing::decodeCapture(capture, ogf::velodyne::StreamConfig{});
  Expected want = rejectedInTheCapture(expected.counters);
  BadDatagrams bad(data_port, position_port, want);
  ASSERT_TRUE(bad.ok());
  const std::int64_t data_sent = sendCaptureWithBadDatagrams(capture, data_port, position_port, bad);
  ASSERT_GT(data_sent, kCleanStart);
  const std::int64_t want_data = expected.counters.data_packets;
  const std::int64_t want_position = expected.counters.position_packets + want.extra_position;

  EXPECT_TRUE(countedInStatus(driver, want, want_data, want_position));
  EXPECT_TRUE(driver.running()) << "the driver exited:\n" << driver.log();
  ASSERT_TRUE(driver.stop());  // SIGTERM publishes the scan in progress
  std::this_thread::sleep_for(500ms);

  const auto got = scans.messages();
  const std::int64_t points = expectTheCleanDecode(got, expected.scans);
  std::printf("[ figures  ] driver bad input: %lld valid data + %lld position packets, bad_size %lld, "
              "bad_block_flag %lld, bad_other %lld, foreign_sender %lld counted; %zu scans (%lld points) "
              "identical to the clean decode\n",
              static_cast<long long>(want_data), static_cast<long long>(want_position),
              static_cast<long long>(want.bad_size), static_cast<long long>(want.bad_block_flag),
              static_cast<long long>(want.bad_other), static_cast<long long>(want.foreign), got.size(),
              static_cast<long long>(points));
  fs::remove(log);
}

}  // namespace
