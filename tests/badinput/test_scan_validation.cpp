// validateScan, the check ogf-mapper and ogf-map apply to every decoded lidar_scan_t before it is queued:
// a scan no sender makes (NaN or infinite coordinates, times no clock gives, negative time offsets, end before
// start) is refused with an error naming the field, and a well-formed one passes; likewise a POSE at a time
// no clock gives (decodePose).
#include <gtest/gtest.h>

#include <ogf/odometry_t.hpp>

#include <cstdint>
#include <limits>

#include "lcm_bytes.hpp"
#include "ogf/adapters/message_adapters.hpp"

namespace {

ogf::lidar_scan_t threePoints() {
  ogf::lidar_scan_t s{};
  s.device_utime_start = s.host_utime_start = 1000;
  s.device_utime_end = s.host_utime_end = 2000;
  s.num_points = 3;
  s.x = {1, 2, 3};
  s.y = {0, 0, 0};
  s.z = {0.5f, 0.5f, 0.5f};
  s.time_offset_ns = {0, 10, 20};
  s.intensity = {1, 1, 1};
  s.ring = s.laser_id = s.return_type = {0, 0, 0};
  s.azimuth_deg = {0, 1, 2};
  return s;
}

std::string whyRefused(const ogf::lidar_scan_t& s) {
  const auto st = ogf::adapters::validateScan(s);
  return st ? std::string("accepted") : st.error().message;
}

TEST(ScanValidation, AWellFormedScanPasses) { EXPECT_EQ(whyRefused(threePoints()), "accepted"); }

TEST(ScanValidation, NonFiniteCoordinatesAreRefusedNamingThePoint) {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
    for (int axis = 0; axis < 3; ++axis) {
      auto s = threePoints();
      (axis == 0 ? s.x : axis == 1 ? s.y : s.z)[1] = bad;
      EXPECT_EQ(whyRefused(s), "x/y/z[1]: not finite") << "axis " << axis << " value " << bad;
    }
  }
}

TEST(ScanValidation, CountsTimesAndOffsetsAreChecked) {
  auto s = threePoints();
  s.time_offset_ns[2] = -1;
  EXPECT_EQ(whyRefused(s), "time_offset_ns[2]: negative");
  s = threePoints();
  s.device_utime_end = 999;
  EXPECT_EQ(whyRefused(s), "device_utime_end: before device_utime_start");
  s = threePoints();
  s.num_points = 4;
  EXPECT_EQ(whyRefused(s), "arrays: lengths differ from num_points 4");
  // A start near the end of int64 would overflow when its points' offsets are added (found by
  // tests/fuzz/messages under UBSan); a negative time is no time either.
  s = threePoints();
  s.device_utime_start = s.device_utime_end = std::numeric_limits<std::int64_t>::max() - 16;
  EXPECT_NE(whyRefused(s).find("device_utime_start: 9223372036854775791 is not a time"), std::string::npos);
  s = threePoints();
  s.host_utime_start = -1;
  EXPECT_NE(whyRefused(s).find("host_utime_start: -1 is not a time"), std::string::npos);
  s = threePoints();
  s.num_points = -1;
  EXPECT_NE(whyRefused(s).find("num_points: -1 outside"), std::string::npos);
}

TEST(PoseValidation, APoseAtATimeNoClockGivesIsRefused) {
  ogf::odometry_t o{};
  o.orientation[0] = 1.0;
  o.utime = 1'700'000'000'000'000;
  auto bytes = ogf::testing::encodeMessage(o);
  EXPECT_TRUE(ogf::adapters::decodePose(bytes.data(), bytes.size()).ok());
  for (const std::int64_t bad : {std::int64_t{-5}, std::numeric_limits<std::int64_t>::max()}) {
    o.utime = bad;
    bytes = ogf::testing::encodeMessage(o);
    const auto pose = ogf::adapters::decodePose(bytes.data(), bytes.size());
    ASSERT_FALSE(pose.ok());
    EXPECT_NE(pose.error().message.find("utime: " + std::to_string(bad) + " is not a time"), std::string::npos);
  }
}

}  // namespace
