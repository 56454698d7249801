// The figures beside the map: the robot's trail keeps positions 5 cm apart, the JSON frame carries only
// the trail points a browser lacks, the mapper's scan rate comes from two statuses, and figures not yet
// known are null.
#include <gtest/gtest.h>

#include "ogf/view/live_figures.hpp"

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

}  // namespace
