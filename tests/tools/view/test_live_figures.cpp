// The figures beside the map: the robot's trail keeps positions 5 cm apart, the JSON frame carries only
// the trail points a browser lacks, the mapper's scan rate comes from two statuses, and figures not yet
// known are null; the mapper's sources arrive with their robot, state, counts and trail.
#include <gtest/gtest.h>

#include "ogf/view/live_figures.hpp"
#include "support/source_status.hpp"

namespace {

using namespace ogf::view;

ogf::fusion::Pose at(double x, std::int64_t utime = 1) {
  ogf::fusion::Pose p;
  p.utime = utime;
  p.position = {x, 0.0, 0.0};
  return p;
}

TEST(PoseTrail, KeepsPositionsAtLeastFiveCentimetresApart) {
  PoseTrail t;
  for (int i = 0; i <= 100; ++i) t.add(at(0.01 * i));  // 1 m in 1 cm steps
  EXPECT_EQ(t.posesSeen(), 101u);
  const auto& pts = t.points();
  ASSERT_GE(pts.size(), 17u);  // 1 m at one point per 5 to 6 cm
  ASSERT_LE(pts.size(), 21u);
  for (std::size_t i = 1; i < pts.size(); ++i) {
    EXPECT_GE(pts[i][0] - pts[i - 1][0], 0.05f - 1e-5f);
    EXPECT_LE(pts[i][0] - pts[i - 1][0], 0.06f + 1e-5f);
  }
  EXPECT_NEAR(t.latest()->position.x(), 1.0, 1e-12);
}

TEST(LiveFigures, UnknownFiguresAreNull) {
  const LiveFigures f;
  StreamFigures s;
  s.source = "live";
  const std::string j = f.json(s, 0, 0);
  EXPECT_NE(j.find(R"("mapper":null)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("driver":null)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("pose":null)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("seq":-1)"), std::string::npos) << j;
}

TEST(LiveFigures, TrailPointsAreSentFromWhereTheBrowserStands) {
  LiveFigures f;
  for (int i = 0; i < 4; ++i) f.trail(false).add(at(i));
  const StreamFigures s;
  const std::string all = f.json(s, 0, 0);
  EXPECT_NE(all.find(R"("trail_from":0,"trail_size":4,"trail":[0.000,0.000,0.000,1.000,)"), std::string::npos) << all;
  const std::string rest = f.json(s, 3, 0);
  EXPECT_NE(rest.find(R"("trail_from":3,"trail_size":4,"trail":[3.000,0.000,0.000])"), std::string::npos) << rest;
}

TEST(LiveFigures, MapperScanRateComesFromTwoStatuses) {
  LiveFigures f;
  ogf::mapper_status_t m{};
  m.utime = 1'000'000;
  m.scans_mapped = 100;
  m.lag_ms = 12.5f;
  f.mapperStatus(m);
  EXPECT_NE(f.json({}, 0, 0).find(R"("scan_rate_hz":null)"), std::string::npos);
  m.utime = 3'000'000;
  m.scans_mapped = 120;
  f.mapperStatus(m);
  const std::string j = f.json({}, 0, 0);
  EXPECT_NE(j.find(R"("scan_rate_hz":10,)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("lag_ms":12.5,)"), std::string::npos) << j;
}

TEST(LiveFigures, StringsAreEscaped) {
  LiveFigures f;
  ogf::driver_status_t d{};
  d.source = "pcap-file \"a\\b\".pcap\n";
  f.driverStatus(d);
  StreamFigures s;
  s.source = "map \"x\"";
  const std::string j = f.json(s, 0, 0);
  EXPECT_NE(j.find(R"("source":"pcap-file \"a\\b\".pcap\u000a")"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("source":"map \"x\"")"), std::string::npos) << j;
}


ogf::source_status_t source(const std::string& name, const std::string& robot, int points) {
  std::vector<std::array<float, 3>> trail;
  for (int i = 0; i < points; ++i) trail.push_back({static_cast<float>(i), 1.5f, 0.25f});
  auto s = ogf::testing::sourceStatus(robot, name, trail);
  s.scans_in = 10;
  s.scans_mapped = 7;
  s.scans_late = 1;
  s.scans_dropped_no_pose = 2;
  return s;
}

TEST(LiveFigures, EachSourceCarriesItsRobotStateCountsAndWholeTrail) {
  LiveFigures f;
  ogf::mapper_status_t m{};
  m.sources = {source("front", "r1", 3), source("rear", "r2", 0)};
  m.num_sources = 2;
  f.mapperStatus(m);
  const std::string j = f.json({}, 0, 0);
  EXPECT_NE(j.find(R"({"name":"front","robot":"r1","scan_channel":"VELODYNE_SCAN_front","packets":false,)"
                   R"("pose_channel":"POSE_r1","inputs":"ok","scans_in":10,"scans_mapped":7,"dropped":3,)"
                   R"("trail":[0.000,1.500,0.250,1.000,1.500,0.250,2.000,1.500,0.250]})"),
            std::string::npos)
      << j;
  EXPECT_NE(j.find(R"({"name":"rear","robot":"r2",)"), std::string::npos) << j;
  EXPECT_NE(j.find(R"("trail":[]}])"), std::string::npos) << j;
}

TEST(LiveFigures, AMapperWithoutSourcesSendsAnEmptyList) {
  LiveFigures f;
  f.mapperStatus(ogf::mapper_status_t{});
  const std::string j = f.json({}, 0, 0);
  EXPECT_NE(j.find(R"("sources":[])"), std::string::npos) << j;
}

}  // namespace
