// Real LCM over udpm:// on loopback: what memq:// cannot show (LCM's queue-capacity drops and the kernel
// receive buffer). Skips with the reason when no multicast route over lo can be arranged.
#include <gtest/gtest.h>

#include <boost/asio/steady_timer.hpp>
#include <lcm/lcm-cpp.hpp>
#include <ogf/lidar_scan_t.hpp>
#include <ogf/map_request_t.hpp>
#include <ogf/odometry_t.hpp>

#include <chrono>
#include <thread>
#include <vector>

#include "ogf/transport/daemon_loop.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/subscriber.hpp"
#include "support/multicast.hpp"

namespace {

using namespace std::chrono_literals;
using ogf::transport::LcmAsioBridge;
using ogf::transport::Subscriber;

class UdpmLoopback : public ::testing::Test {
 protected:
  void SetUp() override {
    if (auto why = ogf::testing::ensureLoopbackMulticast()) GTEST_SKIP() << "udpm on loopback unavailable: " << *why;
  }
};

// Runs the io_context until `done` or the deadline.
void runUntil(boost::asio::io_context& io, const std::function<bool()>& done, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    io.run_for(10ms);
    io.restart();
  }
}

TEST_F(UdpmLoopback, PublishedOdometryArrivesIntactInAnotherLcmInstance) {
  const std::string url = ogf::testing::loopbackUdpmUrl(1);
  lcm::LCM sender(url);
  lcm::LCM receiver(url);
  ASSERT_TRUE(sender.good());
  ASSERT_TRUE(receiver.good());

  boost::asio::io_context io;
  std::vector<ogf::odometry_t> got;
  Subscriber<ogf::odometry_t> sub(receiver, "POSE",
                                  [&](const ogf::odometry_t& m, const lcm::ReceiveBuffer&, const std::string&) { got.push_back(m); },
                                  {});
  LcmAsioBridge bridge(io, receiver);
  std::this_thread::sleep_for(50ms);  // the receive thread joins the group

  ogf::odometry_t msg{};
  msg.utime = 1234567;
  msg.frame_id = "odom";
  msg.child_frame_id = "base_link";
  msg.position[0] = 1.0;
  msg.position[1] = -2.0;
  msg.position[2] = 0.5;
  msg.orientation[0] = 1.0;
  msg.num_covariance = 36;
  msg.covariance.assign(36, 0.01);
  ASSERT_EQ(sender.publish("POSE", &msg), 0);

  runUntil(io, [&] { return !got.empty(); }, 3000ms);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].utime, 1234567);
  EXPECT_EQ(got[0].child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(got[0].position[1], -2.0);
  EXPECT_EQ(got[0].covariance.size(), 36u);
}

TEST_F(UdpmLoopback, FragmentedScanArrivesWhole) {
  // ~30 k points is a real VLP-16 revolution: about 600 KB, ten LCM fragments.
  const std::string url = ogf::testing::loopbackUdpmUrl(2);
  lcm::LCM sender(url);
  lcm::LCM receiver(url);
  ASSERT_TRUE(receiver.good());
  boost::asio::io_context io;
  int points = -1;
  float last_x = 0;
  Subscriber<ogf::lidar_scan_t> sub(receiver, "VELODYNE_SCAN",
                                    [&](const ogf::lidar_scan_t& m, const lcm::ReceiveBuffer&, const std::string&) {
                                      points = m.num_points;
                                      last_x = m.x.back();
                                    },
                                    {});
  LcmAsioBridge bridge(io, receiver);
  std::this_thread::sleep_for(50ms);
  ogf::lidar_scan_t scan{};
  scan.frame_id = "velodyne";
  const int n = 30000;
  scan.num_points = n;
  scan.x.assign(n, 1.f);
  scan.x.back() = 42.f;
  scan.y.assign(n, 2.f);
  scan.z.assign(n, 3.f);
  scan.intensity.assign(n, 7);
  scan.ring.assign(n, 1);
  scan.laser_id.assign(n, 2);
  scan.azimuth_deg.assign(n, 10.f);
  scan.time_offset_ns.assign(n, 100);
  scan.return_type.assign(n, 1);
  ASSERT_GT(scan.getEncodedSize(), 65499);
  sender.publish("VELODYNE_SCAN", &scan);
  runUntil(io, [&] { return points >= 0; }, 3000ms);
  EXPECT_EQ(points, n);
  EXPECT_EQ(last_x, 42.f);
}

TEST_F(UdpmLoopback, AsioBridgeDeliversABurstOf1000WithoutLoss) {
  // LCM's default queue of 30 would keep 31 of these (the newest dropped); the raised capacity and
  // receive buffer must keep all 1000, delivered in order.
  const std::string url = ogf::testing::loopbackUdpmUrl(3);
  lcm::LCM sender(url);
  lcm::LCM receiver(url);
  ASSERT_TRUE(receiver.good());
  ogf::transport::DaemonLoop loop;
  std::vector<std::int64_t> seqs;
  int errors = 0;
  Subscriber<ogf::map_request_t> sub(
      receiver, "OGF_MAP_REQUEST",
      [&](const ogf::map_request_t& m, const lcm::ReceiveBuffer&, const std::string&) { seqs.push_back(m.last_seq); },
      [&](const std::string&, std::size_t, std::string_view) { ++errors; });
  LcmAsioBridge bridge(loop.io(), receiver);
  std::this_thread::sleep_for(50ms);

  // The burst is published before the loop runs at all: everything waits in LCM's queue.
  ogf::map_request_t req{};
  req.requester = std::string(1100, 'r');  // ~1.2 KB, like a raw packet message
  constexpr int kBurst = 1000;
  for (int i = 0; i < kBurst; ++i) {
    req.last_seq = i;
    ASSERT_EQ(sender.publish("OGF_MAP_REQUEST", &req), 0);
  }
  runUntil(loop.io(), [&] { return seqs.size() >= kBurst; }, 5000ms);
  ASSERT_EQ(seqs.size(), static_cast<std::size_t>(kBurst));
  for (int i = 0; i < kBurst; ++i) ASSERT_EQ(seqs[static_cast<std::size_t>(i)], i);
  EXPECT_EQ(errors, 0);
  EXPECT_GE(bridge.dispatched(), static_cast<std::uint64_t>(kBurst));
}

TEST_F(UdpmLoopback, MessageOfAnotherTypeIsReportedNotDelivered) {
  const std::string url = ogf::testing::loopbackUdpmUrl(4);
  lcm::LCM sender(url);
  lcm::LCM receiver(url);
  boost::asio::io_context io;
  int delivered = 0;
  std::vector<std::string> reasons;
  Subscriber<ogf::odometry_t> sub(
      receiver, "POSE", [&](const ogf::odometry_t&, const lcm::ReceiveBuffer&, const std::string&) { ++delivered; },
      [&](const std::string& ch, std::size_t, std::string_view why) { reasons.push_back(ch + ": " + std::string(why)); });
  LcmAsioBridge bridge(io, receiver);
  std::this_thread::sleep_for(50ms);
  ogf::map_request_t wrong{};
  wrong.requester = "x";
  sender.publish("POSE", &wrong);
  const char garbage[5] = {1, 2, 3, 4, 5};
  sender.publish("POSE", garbage, sizeof(garbage));
  runUntil(io, [&] { return reasons.size() >= 2; }, 3000ms);
  EXPECT_EQ(delivered, 0);
  ASSERT_EQ(reasons.size(), 2u);
  EXPECT_NE(reasons[0].find("POSE"), std::string::npos);
}

}  // namespace
