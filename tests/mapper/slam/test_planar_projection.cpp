// A planar scan from 3-D points: the height band, the nearest point per bearing bin, empty bins as
// "no return", the wrap at ±π.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <ogf/slam/planar_projection.hpp>
#include <vector>

namespace ogf::slam {
namespace {

std::size_t binOf(const PlanarScan& s, double bearing) {
  return static_cast<std::size_t>(std::lround((bearing - s.angle_min_rad) / s.angle_increment_rad)) %
         s.ranges_m.size();
}

TEST(PlanarProjection, KeepsTheNearestPointInTheBandPerBearing) {
  PlanarProjectionConfig c;
  c.beams = 360;
  const std::vector<Eigen::Vector3f> pts{
      {3.0F, 0.0F, 0.5F},  // ahead, in the band
      {2.0F, 0.0F, 0.5F},  // ahead, nearer: wins
      {1.0F, 0.0F, 2.5F},  // ahead, above the band: dropped
      {0.5F, 0.0F, 0.0F},  // ahead, below the band: dropped
      {0.0F, 4.0F, 1.0F},  // left
      {0.2F, 0.0F, 0.5F},  // closer than min_range: dropped
  };
  const PlanarScan s = projectToPlanarScan(pts, c);
  ASSERT_EQ(s.ranges_m.size(), 360U);
  EXPECT_FLOAT_EQ(s.ranges_m[binOf(s, 0.0)], 2.0F);
  EXPECT_FLOAT_EQ(s.ranges_m[binOf(s, std::numbers::pi / 2)], 4.0F);
  EXPECT_TRUE(s.isNoReturn(s.ranges_m[binOf(s, -std::numbers::pi / 2)]));
  EXPECT_NEAR(s.bearing(binOf(s, std::numbers::pi / 2)), std::numbers::pi / 2, 1e-9);
}

TEST(PlanarProjection, BearingsNearPlusAndMinusPiShareTheFirstBin) {
  PlanarProjectionConfig c;
  c.beams = 8;
  const std::vector<Eigen::Vector3f> pts{{-5.0F, 0.01F, 0.5F}, {-3.0F, -0.01F, 0.5F}};
  const PlanarScan s = projectToPlanarScan(pts, c);
  EXPECT_FLOAT_EQ(s.ranges_m[0], static_cast<float>(std::hypot(3.0, 0.01)));
}

TEST(PlanarProjection, RejectsABandUpsideDown) {
  PlanarProjectionConfig c;
  c.z_min_m = 1.0;
  c.z_max_m = 0.5;
  EXPECT_FALSE(c.validate().ok());
}

}  // namespace
}  // namespace ogf::slam
