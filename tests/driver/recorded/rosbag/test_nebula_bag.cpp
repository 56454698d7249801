// The real ROS 2 bag (tier4/nebula, a VLP-16 in dual return mode, ../shared/data/real/nebula_vlp16_dual)
// decodes to exactly the scans of the pcap derived from it (same payloads, stamps as record times): every
// scan's times, packet counts and every point, and the same CRC-32 of each scan's points.
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>

#include "capture_decoding.hpp"
#include "ogf/common/crc32.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/rosbag/ros_messages.hpp"
#include "ogf/rosbag/rosbag2_storage.hpp"
#include "ogf/velodyne/packet_stream.hpp"
#include "support/shared_data.hpp"

namespace {

namespace ov = ogf::velodyne;

constexpr const char* kBag = "data/real/nebula_vlp16_dual/1673400471837873222";
constexpr const char* kDerivedPcap = "data/real/derived/nebula_vlp16_dual_1673400471837873222.DERIVED.pcap";

// CRC-32 of a scan's points, field by field (no padding bytes).
std::uint32_t pointsCrc(const ov::Scan& scan) {
  std::uint32_t crc = 0;
  const auto add = [&crc](const auto& v) { crc = ogf::crc32(std::as_bytes(std::span(&v, 1)), crc); };
  for (const ov::ScanPoint& p : scan.points) {
    add(p.x), add(p.y), add(p.z), add(p.distance_m), add(p.azimuth_deg), add(p.time_offset_ns);
    add(p.intensity), add(p.ring), add(p.laser_id), add(p.return_type);
  }
  return crc;
}

TEST(NebulaBag, DecodesToExactlyTheScansOfItsDerivedPcap) {
  OGF_REQUIRE_SHARED_FILE(bag_dir, kBag);
  OGF_REQUIRE_SHARED_FILE(pcap, kDerivedPcap);
  const ogf::testing::DecodedCapture expected = ogf::testing::decodeCapture(pcap);
  ASSERT_TRUE(expected.read_error.empty()) << expected.read_error;

  auto bag = ogf::rosbag::Rosbag2Storage::open(bag_dir);
  ASSERT_TRUE(bag) << bag.error().message;
  ASSERT_EQ(bag->topics().size(), 1U);
  EXPECT_EQ(bag->topics()[0].name, "/velodyne_packets");
  EXPECT_EQ(bag->topics()[0].type, ogf::rosbag::kVelodyneScanType);
  EXPECT_EQ(bag->topics()[0].message_count, 4);
  auto stream = ov::PacketStream::create(ov::StreamConfig{});
  ASSERT_TRUE(stream) << stream.error().message;
  std::vector<ov::Scan> scans;
  stream->setScanSink([&](const ov::Scan& s) { scans.push_back(s); });
  auto counts = ogf::rosbag::readBagPackets(*bag, "/velodyne_packets", [&](const ogf::rosbag::BagPacket& p) {
    stream->addDataPacket(p.payload, p.host_utime);
  });
  ASSERT_TRUE(counts) << counts.error().message;
  stream->finish();
  EXPECT_EQ(counts->messages, 4);
  EXPECT_EQ(counts->packets, 603);  // docs/test-data.md §2.3: 603 data packets
  EXPECT_EQ(counts->skipped, 0);
  EXPECT_EQ(counts->gaps.gaps(), 0);

  EXPECT_EQ(stream->counters().data_packets, expected.counters.data_packets);
  EXPECT_EQ(stream->counters().scans, expected.counters.scans);
  EXPECT_EQ(stream->counters().bad_size + stream->counters().bad_block_flag + stream->counters().bad_other,
            0);
  EXPECT_EQ(stream->model(), ov::Model::Vlp16);
  EXPECT_EQ(stream->returnMode(), ov::ReturnMode::Dual);
  ASSERT_EQ(scans.size(), expected.scans.size());
  std::int64_t points = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const ov::Scan& a = scans[i];
    const ov::Scan& b = expected.scans[i];
    SCOPED_TRACE("scan " + std::to_string(i));
    EXPECT_EQ(a.seq, b.seq);
    EXPECT_EQ(a.device_utime_start, b.device_utime_start);
    EXPECT_EQ(a.device_utime_end, b.device_utime_end);
    EXPECT_EQ(a.host_utime_start, b.host_utime_start);
    EXPECT_EQ(a.host_utime_end, b.host_utime_end);
    EXPECT_EQ(a.packets_expected, b.packets_expected);
    EXPECT_EQ(a.packets_received, b.packets_received);
    EXPECT_EQ(a.packets_lost, b.packets_lost);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_EQ(pointsCrc(a), pointsCrc(b));
    for (std::size_t k = 0; k < a.points.size(); ++k) {
      const ov::ScanPoint& p = a.points[k];
      const ov::ScanPoint& q = b.points[k];
      ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z && p.intensity == q.intensity && p.ring == q.ring &&
                  p.time_offset_ns == q.time_offset_ns && p.return_type == q.return_type)
          << "point " << k;
    }
    points += static_cast<std::int64_t>(a.points.size());
  }
  std::cout << "nebula bag: " << scans.size() << " scans, " << points << " points, "
            << stream->counters().data_packets << " packets, equal to the derived pcap\n";
}

}  // namespace
