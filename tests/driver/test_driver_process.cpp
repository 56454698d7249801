// ogf-driver as a real process on real LCM udpm over loopback: a capture replayed through it gives the
// same scans as the library, its raw packet batches decode again to the same scans, and on the UDP source
// wrong-size, bad-flag and foreign datagrams are counted in VELODYNE_STATUS while it keeps running; the
// receive buffer it reports is the one the kernel granted; its log names the calibration it decodes with.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <optional>
#include <thread>
#include <utility>

#include "capture_decoding.hpp"
#include "support/child_process.hpp"
#include "support/daemon_process.hpp"
#include "ogf/driver_status_t.hpp"
#include "ogf/lidar_scan_t.hpp"
#include "ogf/transport/subscriber.hpp"
#include "ogf/velodyne_packets_t.hpp"
#include "support/multicast.hpp"
#include "support/shared_data.hpp"

namespace ov = ogf::velodyne;
using ogf::testing::ChildProcess;

namespace {

constexpr const char* kCapture = "data/real/sampleShort.pcap";

struct Bus {
  explicit Bus(const std::string& url) : lcm(url) {}
  lcm::LCM lcm;
  std::vector<ogf::lidar_scan_t> scans;
  std::vector<ogf::velodyne_packets_t> packets;
  std::vector<ogf::driver_status_t> statuses;

  // Handles messages until `done` or `timeout`.
  template <class Done>
  void pump(Done done, std::chrono::milliseconds timeout) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!done() && std::chrono::steady_clock::now() < end) lcm.handleTimeout(50);
  }
  // Handles messages until none arrives for `quiet`.
  void drain(std::chrono::milliseconds quiet) {
    while (lcm.handleTimeout(static_cast<int>(quiet.count())) > 0) {
    }
  }
};

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))).string();
}

// Sends one datagram from `sock` to 127.0.0.1:`port`.
void sendToLoopback(int sock, int port, const std::uint8_t* data, std::size_t n) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(0x7F000001);
  ::sendto(sock, data, n, 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
}

// Stops the driver with SIGTERM, expects a clean exit and returns its last status.
ogf::driver_status_t stopAndLastStatus(ChildProcess& driver, Bus& bus) {
  EXPECT_TRUE(ogf::testing::stopWithSigterm(driver, std::chrono::seconds(10)));
  bus.drain(std::chrono::milliseconds(300));
  return bus.statuses.back();
}

void expectSameScans(const std::vector<ov::Scan>& expected, const std::vector<ogf::lidar_scan_t>& got) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    const auto& e = expected[i];
    const auto& g = got[i];
    ASSERT_EQ(static_cast<std::size_t>(g.num_points), e.points.size()) << "scan " << i;
    EXPECT_EQ(g.device_utime_start, e.device_utime_start);
    EXPECT_EQ(g.packets_received, e.packets_received);
    EXPECT_EQ(g.time_source, static_cast<std::int8_t>(e.time_source));
    for (std::size_t p = 0; p < e.points.size(); p += 97) {
      EXPECT_EQ(g.x[p], e.points[p].x);
      EXPECT_EQ(g.z[p], e.points[p].z);
      EXPECT_EQ(g.time_offset_ns[p], e.points[p].time_offset_ns);
      EXPECT_EQ(g.ring[p], static_cast<std::int8_t>(e.points[p].ring));
    }
  }
}

}  // namespace

TEST(DriverProcess, ReplayedCapturePublishesTheLibrarysScansAndRawPacketsThatDecodeAgain) {
  OGF_REQUIRE_SHARED_FILE(capture, kCapture);
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(31);
  Bus bus(url);
  ASSERT_TRUE(bus.lcm.good());
  auto on_error = [](const std::string&, std::size_t, std::string_view) {
    ADD_FAILURE() << "undecodable message";
  };
  ogf::transport::Subscriber<ogf::lidar_scan_t> scans(
      bus.lcm, "TEST_SCAN", [&](const auto& m, const auto&, const auto&) { bus.scans.push_back(m); },
      on_error);
  ogf::transport::Subscriber<ogf::velodyne_packets_t> packets(
      bus.lcm, "TEST_PACKETS", [&](const auto& m, const auto&, const auto&) { bus.packets.push_back(m); },
      on_error);
  ogf::transport::Subscriber<ogf::driver_status_t> status(
      bus.lcm, "TEST_STATUS", [&](const auto& m, const auto&, const auto&) { bus.statuses.push_back(m); },
      on_error);

  ChildProcess driver(
      {OGF_DRIVER_BINARY, "--pcap", capture.string(), "--speed", "1", "--lcm-url", url, "--min-range", "0",
       "--scan-channel", "TEST_SCAN", "--packets-channel", "TEST_PACKETS", "--status-channel", "TEST_STATUS"},
      tempPath("ogf-driver-replay.log"));
  ASSERT_TRUE(driver.started());
  std::optional<int> exit_code;
  bus.pump([&] { return (exit_code = driver.wait(std::chrono::milliseconds(0))).has_value(); },
           std::chrono::seconds(30));
  bus.drain(std::chrono::milliseconds(500));
  ASSERT_EQ(exit_code, 0) << driver.log();

  ov::StreamConfig config;
  config.min_range_m = 0.0;
  const auto expected = ogf::testing::decodeCapture(capture, config);
  expectSameScans(expected.scans, bus.scans);
  ASSERT_FALSE(bus.statuses.empty());
  const auto& last = bus.statuses.back();
  EXPECT_EQ(last.data_packets, 291);
  EXPECT_EQ(last.position_packets, 56);
  EXPECT_EQ(last.scans_published, 5);
  EXPECT_EQ(last.pps_state, ogf::driver_status_t::PPS_LOCKED);
  EXPECT_TRUE(last.gps_fix_valid);
  EXPECT_EQ(last.model, ogf::lidar_scan_t::MODEL_VLP16);
  EXPECT_GE(last.bad_other, 1);  // the truncated last record

  // The raw batches, decoded again, give the same scans.
  auto stream = ov::PacketStream::create(config);
  ASSERT_TRUE(stream);
  std::vector<ov::Scan> again;
  stream->setScanSink([&again](const ov::Scan& s) { again.push_back(s); });
  std::int64_t raw = 0;
  for (const auto& batch : bus.packets) {
    std::size_t offset = 0;
    for (int i = 0; i < batch.num_packets; ++i) {
      const auto n = static_cast<std::size_t>(batch.length[static_cast<std::size_t>(i)]);
      const std::span<const std::uint8_t> payload(batch.data.data() + offset, n);
      offset += n;
      if (batch.port[static_cast<std::size_t>(i)] == 2368)
        stream->addDataPacket(payload, batch.host_utime[static_cast<std::size_t>(i)]);
      else
        stream->addPositionPacket(payload, batch.host_utime[static_cast<std::size_t>(i)]);
      ++raw;
    }
  }
  stream->finish();
  EXPECT_EQ(raw, 291 + 56);
  ASSERT_EQ(again.size(), expected.scans.size());
  for (std::size_t i = 0; i < again.size(); ++i) {
    ASSERT_EQ(again[i].points.size(), expected.scans[i].points.size());
    EXPECT_EQ(again[i].device_utime_start, expected.scans[i].device_utime_start);
  }
}

TEST(DriverProcess, UdpSourceCountsGarbageAndForeignSendersAndKeepsDecoding) {
  OGF_REQUIRE_SHARED_FILE(capture, kCapture);
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(37);
  Bus bus(url);
  ASSERT_TRUE(bus.lcm.good());
  auto on_error = [](const std::string&, std::size_t, std::string_view) {};
  ogf::transport::Subscriber<ogf::driver_status_t> status(
      bus.lcm, "UDP_TEST_STATUS", [&](const auto& m, const auto&, const auto&) { bus.statuses.push_back(m); },
      on_error);
  ogf::transport::Subscriber<ogf::lidar_scan_t> scans(
      bus.lcm, "UDP_TEST_SCAN", [&](const auto& m, const auto&, const auto&) { bus.scans.push_back(m); },
      on_error);

  const int data_port = 30000 + static_cast<int>(::getpid() % 20000);
  const int position_port = data_port + 1;
  ChildProcess driver(
      {OGF_DRIVER_BINARY, "--bind-address", "127.0.0.1", "--data-port", std::to_string(data_port),
       "--position-port", std::to_string(position_port), "--sensor-ip", "127.0.0.1", "--lcm-url", url,
       "--scan-channel", "UDP_TEST_SCAN", "--status-channel", "UDP_TEST_STATUS", "--no-packets"},
      tempPath("ogf-driver-udp.log"));
  ASSERT_TRUE(driver.started());
  // Ready once it publishes its first status.
  bus.pump([&] { return !bus.statuses.empty(); }, std::chrono::seconds(10));
  ASSERT_FALSE(bus.statuses.empty()) << driver.log();

  const int sock = ::socket(AF_INET, SOCK_DGRAM, 0);
  const int foreign = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in from{};
  from.sin_family = AF_INET;
  from.sin_addr.s_addr = htonl(0x7F000002);  // 127.0.0.2: another host on the lidar LAN
  ASSERT_EQ(::bind(foreign, reinterpret_cast<sockaddr*>(&from), sizeof(from)), 0);
  auto sendTo = sendToLoopback;
  auto reader = ogf::driver_sources::PcapFileReader::open(capture);
  ASSERT_TRUE(reader);
  ogf::driver_sources::PcapRecord record;
  std::int64_t data_sent = 0, position_sent = 0;
  const std::vector<std::uint8_t> garbage(100, 0x42);
  std::vector<std::uint8_t> bad_flag;
  while ((*reader)->next(record) != ogf::driver_sources::ReadStatus::End && (*reader)->error().empty()) {
    if (record.kind != ogf::driver_sources::FrameKind::Udp) continue;
    const auto& d = record.datagram;
    if (d.destination_port == 2368) {
      sendTo(sock, data_port, d.payload.data(), d.payload.size());
      ++data_sent;
      if (bad_flag.empty()) bad_flag.assign(d.payload.begin(), d.payload.end());
      if (data_sent % 50 == 0) {
        sendTo(sock, data_port, garbage.data(), garbage.size());         // wrong size
        sendTo(foreign, data_port, d.payload.data(), d.payload.size());  // another host
      }
    } else if (d.destination_port == 8308) {
      sendTo(sock, position_port, d.payload.data(), d.payload.size());
      ++position_sent;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(300));  // about the sensor's own rate
  }
  bad_flag[100] = 0x00;  // block 1's flag
  sendTo(sock, data_port, bad_flag.data(), bad_flag.size());
  ::close(sock);
  ::close(foreign);
  const std::int64_t garbage_sent = data_sent / 50;
  bus.pump(
      [&] {
        const auto& s = bus.statuses.back();
        return s.data_packets == data_sent && s.position_packets == position_sent &&
               s.bad_size == garbage_sent && s.foreign_sender == garbage_sent && s.bad_block_flag == 1;
      },
      std::chrono::seconds(15));
  const auto s = stopAndLastStatus(driver, bus);
  EXPECT_EQ(s.data_packets, data_sent);
  EXPECT_EQ(s.position_packets, position_sent);
  EXPECT_EQ(s.bad_size, garbage_sent);
  EXPECT_EQ(s.foreign_sender, garbage_sent);
  EXPECT_EQ(s.bad_block_flag, 1);
  EXPECT_GT(s.socket_receive_buffer, 0);
  EXPECT_EQ(s.pps_state, ogf::driver_status_t::PPS_LOCKED);
  EXPECT_NE(s.source.find("udp 127.0.0.1:"), std::string::npos);
  // Decoding went on through the garbage: the capture's 4 wraps give at least 4 scans before SIGTERM.
  EXPECT_GE(bus.scans.size(), 4u);
  EXPECT_NE(driver.log().find("expected 1206"), std::string::npos);
}

TEST(DriverProcess, BadConfigurationStopsAtStartUpNamingTheSetting) {
  const std::string yaml = tempPath("ogf-driver-bad.yaml");
  { std::ofstream(yaml) << "data_port: 2368\nmin_range: 5\nmax_range: 1\n"; }
  ChildProcess ranges({OGF_DRIVER_BINARY, "--config", yaml}, tempPath("ogf-driver-bad.log"));
  EXPECT_EQ(ranges.wait(std::chrono::seconds(10)), 2);
  EXPECT_NE(ranges.log().find("min_range"), std::string::npos) << ranges.log();
  { std::ofstream(yaml) << "data_port: 2368\ncut_angel: 90\n"; }
  ChildProcess unknown({OGF_DRIVER_BINARY, "--config", yaml}, tempPath("ogf-driver-bad.log"));
  EXPECT_EQ(unknown.wait(std::chrono::seconds(10)), 2);
  EXPECT_NE(unknown.log().find(":2: cut_angel: unknown setting"), std::string::npos) << unknown.log();
  { std::ofstream(yaml) << "model: HDL-64E\n"; }
  ChildProcess model({OGF_DRIVER_BINARY, "--config", yaml, "--data-port", "2400"},
                     tempPath("ogf-driver-bad.log"));
  EXPECT_EQ(model.wait(std::chrono::seconds(10)), 2);
  EXPECT_NE(model.log().find("model: 'HDL-64E'"), std::string::npos) << model.log();
  // A flag overrides the file.
  ChildProcess fixed(
      {OGF_DRIVER_BINARY, "--config", yaml, "--model", "VLP-16", "--pcap", "/nonexistent.pcap"},
      tempPath("ogf-driver-bad.log"));
  EXPECT_EQ(fixed.wait(std::chrono::seconds(10)), 1);  // past validation, then the file is missing
  EXPECT_NE(fixed.log().find("/nonexistent.pcap"), std::string::npos) << fixed.log();
  std::filesystem::remove(yaml);
}

TEST(DriverProcess, LiveCaptureOnLoopbackDecodesTheSensorTraffic) {
  OGF_REQUIRE_SHARED_FILE(capture, kCapture);
  if (::geteuid() != 0) GTEST_SKIP() << "live capture needs CAP_NET_RAW (run as root)";
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const std::string url = ogf::testing::loopbackUdpmUrl(41);
  Bus bus(url);
  auto on_error = [](const std::string&, std::size_t, std::string_view) {};
  ogf::transport::Subscriber<ogf::driver_status_t> status(
      bus.lcm, "LIVE_TEST_STATUS",
      [&](const auto& m, const auto&, const auto&) { bus.statuses.push_back(m); }, on_error);
  const int data_port = 35000 + static_cast<int>(::getpid() % 20000);
  ChildProcess driver({OGF_DRIVER_BINARY, "--interface", "lo", "--data-port", std::to_string(data_port),
                       "--position-port", std::to_string(data_port + 1), "--lcm-url", url, "--status-channel",
                       "LIVE_TEST_STATUS", "--scan-channel", "LIVE_TEST_SCAN", "--no-packets"},
                      tempPath("ogf-driver-live.log"));
  bus.pump([&] { return !bus.statuses.empty(); }, std::chrono::seconds(10));
  ASSERT_FALSE(bus.statuses.empty()) << driver.log();
  const int sock = ::socket(AF_INET, SOCK_DGRAM, 0);
  auto reader = ogf::driver_sources::PcapFileReader::open(capture);
  ASSERT_TRUE(reader);
  ogf::driver_sources::PcapRecord record;
  std::int64_t data_sent = 0, position_sent = 0;
  while ((*reader)->next(record) == ogf::driver_sources::ReadStatus::Datagram && data_sent < 150) {
    const auto& d = record.datagram;
    const bool data = d.destination_port == 2368;
    sendToLoopback(sock, data ? data_port : data_port + 1, d.payload.data(), d.payload.size());
    (data ? data_sent : position_sent) += 1;
    std::this_thread::sleep_for(std::chrono::microseconds(300));
  }
  ::close(sock);
  bus.pump([&] { return bus.statuses.back().data_packets >= data_sent; }, std::chrono::seconds(10));
  const auto s = stopAndLastStatus(driver, bus);
  EXPECT_EQ(s.data_packets, data_sent);
  EXPECT_EQ(s.position_packets, position_sent);
  EXPECT_EQ(s.source, "pcap-live lo");
  EXPECT_GT(s.scans_published, 0);
}

namespace {

std::optional<long long> rmemMax() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  long long v = 0;
  if (!(in >> v)) return std::nullopt;
  return v;
}

// Starts the driver on UDP asking for `bytes` of receive buffer, returns its first status and its log.
std::pair<ogf::driver_status_t, std::string> statusAskingForBuffer(long long bytes, int slot) {
  const std::string url = ogf::testing::loopbackUdpmUrl(slot);
  const int data_port = 36000 + static_cast<int>(::getpid() % 20000) + 2 * slot;
  ogf::testing::DaemonProcess<ogf::driver_status_t> driver(
      {OGF_DRIVER_BINARY, "--bind-address", "127.0.0.1", "--data-port", std::to_string(data_port), "--position-port",
       std::to_string(data_port + 1), "--lcm-url", url, "--status-channel", "RCVBUF_TEST_STATUS", "--receive-buffer",
       std::to_string(bytes)},
      tempPath("ogf-driver-rcvbuf-" + std::to_string(slot) + ".log"), url, "RCVBUF_TEST_STATUS");
  const auto first = driver.waitForStatus([](const ogf::driver_status_t&) { return true; }, std::chrono::seconds(15));
  EXPECT_TRUE(driver.stop(std::chrono::seconds(10)));
  EXPECT_TRUE(first) << driver.log();
  return {first.value_or(ogf::driver_status_t{}), driver.log()};
}

}  // namespace

TEST(DriverProcess, ReceiveBufferIsTheSizeAskedUpToRmemMaxAndRmemMaxWithAWarningBeyond) {
  if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << *why;
  const auto max = rmemMax();
  if (!max) GTEST_SKIP() << "/proc/sys/net/core/rmem_max unreadable";
  if (*max < 2 * 65536 || *max > (1LL << 29)) GTEST_SKIP() << "net.core.rmem_max=" << *max << " out of the tested range";
  // Within the limit: exactly what was asked, without a warning.
  const long long within = *max / 2;
  const auto [granted, quiet_log] = statusAskingForBuffer(within, 43);
  EXPECT_EQ(granted.socket_receive_buffer, within) << quiet_log;
  EXPECT_EQ(quiet_log.find("receive buffer"), std::string::npos) << quiet_log;
  // Beyond it: the limit, and a warning naming the granted size and the sysctl.
  const long long beyond = *max * 2;
  const auto [capped, warned_log] = statusAskingForBuffer(beyond, 44);
  EXPECT_EQ(capped.socket_receive_buffer, *max) << warned_log;
  EXPECT_NE(warned_log.find("the kernel granted a " + std::to_string(*max) + " byte receive buffer, less than the " +
                            std::to_string(beyond) + " asked for"),
            std::string::npos)
      << warned_log;
  EXPECT_NE(warned_log.find("sysctl -w net.core.rmem_max=" + std::to_string(beyond)), std::string::npos) << warned_log;
}

TEST(DriverProcess, WithoutCalibNamesTheEmbeddedTableOfTheDetectedModelOnce) {
  OGF_REQUIRE_SHARED_FILE(capture, kCapture);
  OGF_REQUIRE_SHARED_FILE(xml, "data/real/calib/VLP-16.xml");
  const std::string url = "memq://";
  ChildProcess nominal({OGF_DRIVER_BINARY, "--pcap", capture.string(), "--speed", "0", "--lcm-url", url},
                       tempPath("ogf-driver-calib-nominal.log"));
  ASSERT_EQ(nominal.wait(std::chrono::seconds(30)), 0) << nominal.log();
  const std::string log = nominal.log();
  const std::string line = "sensor model VLP-16 (detected); calibration: the embedded nominal VLP-16 table";
  EXPECT_NE(log.find(line), std::string::npos) << log;
  EXPECT_EQ(log.find(line), log.rfind(line)) << "said more than once\n" << log;
  ChildProcess file({OGF_DRIVER_BINARY, "--pcap", capture.string(), "--speed", "0", "--lcm-url", url, "--calib",
                     xml.string(), "--model", "VLP-16"},
                    tempPath("ogf-driver-calib-file.log"));
  ASSERT_EQ(file.wait(std::chrono::seconds(30)), 0) << file.log();
  EXPECT_NE(file.log().find("sensor model VLP-16 (configured); calibration: " + xml.string()), std::string::npos)
      << file.log();
}
