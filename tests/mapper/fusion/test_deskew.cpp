// Deskew: a sensor moving at constant velocity and yawing while it scans a known wall. Placed with the
// pose at each point's time, every point lands on the wall to float precision; placed with the scan-start
// pose, they do not. Also: all-or-nothing coverage, one interpolation per distinct firing time.
#include <ogf/fusion/deskew.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace ogf::fusion {
namespace {

constexpr std::int64_t kScanStart = 1'700'000'000'000'000;  // µs
constexpr double kWallX = 10.0;                              // the wall is the plane x = 10 m (odometry frame)

Pose truePose(std::int64_t utime) {
  const double s = static_cast<double>(utime - kScanStart) * 1e-6;
  Pose p;
  p.utime = utime;
  p.position = Eigen::Vector3d(1.0, 0.5, 0.0) * s + Eigen::Vector3d(-2.0, 1.0, 0.0);  // 1.1 m/s
  p.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 + 0.8 * s, Eigen::Vector3d::UnitZ()));  // 0.8 rad/s
  return p;
}

Eigen::Isometry3d extrinsic() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(0.3, 0.1, 0.8);
  return t;
}

struct WallScan {
  std::vector<float> x, y, z;
  std::vector<std::int32_t> offset_ns;
  ScanPoints view() const { return {kScanStart, x, y, z, offset_ns}; }
};

// 900 firings of 16 lasers over 100 ms, sweeping azimuth -40°..+40° in the sensor frame; each point is the
// true intersection with the wall, expressed in the sensor frame at its own time.
WallScan wallScan() {
  WallScan scan;
  const double deg = std::numbers::pi / 180.0;
  for (int firing = 0; firing < 900; ++firing) {
    const auto offset_ns = static_cast<std::int32_t>(firing * 111'111);
    const std::int64_t t = kScanStart + (std::int64_t{offset_ns} + 500) / 1000;
    const Eigen::Isometry3d odom_from_sensor = truePose(t).odomFromBody() * extrinsic();
    const double azimuth = (-40.0 + 80.0 * firing / 899.0) * deg;
    for (int laser = 0; laser < 16; ++laser) {
      const double elevation = (-15.0 + 2.0 * laser) * deg;
      const Eigen::Vector3d dir_s(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                                  std::sin(elevation));
      const Eigen::Vector3d dir = odom_from_sensor.linear() * dir_s;
      const Eigen::Vector3d o = odom_from_sensor.translation();
      const Eigen::Vector3d hit = o + dir * ((kWallX - o.x()) / dir.x());
      const Eigen::Vector3d p = odom_from_sensor.inverse() * hit;
      scan.x.push_back(static_cast<float>(p.x()));
      scan.y.push_back(static_cast<float>(p.y()));
      scan.z.push_back(static_cast<float>(p.z()));
      scan.offset_ns.push_back(offset_ns);
    }
  }
  return scan;
}

PoseBuffer odometry(std::int64_t from, std::int64_t to) {
  PoseBufferConfig c;
  c.capacity = 1000;
  PoseBuffer buffer(c);
  for (std::int64_t t = from; t <= to; t += 10'000) EXPECT_TRUE(buffer.insert(truePose(t)).accepted());
  return buffer;
}

TEST(Deskew, PointsOfAMovingTurningSensorLandOnTheWall) {
  const WallScan scan = wallScan();
  const PoseBuffer poses = odometry(kScanStart - 20'000, kScanStart + 120'000);
  Deskew deskew(extrinsic());
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
  ASSERT_EQ(deskew.place(scan.view(), poses, origins, endpoints), PoseCoverage::kCovered);
  ASSERT_EQ(endpoints.size(), scan.x.size());
  double worst = 0.0;
  for (const Eigen::Vector3d& e : endpoints) worst = std::max(worst, std::abs(e.x() - kWallX));
  EXPECT_LT(worst, 1e-4) << "float coordinates at ~10 m carry ~1e-6 m of rounding";
  // The origin of each ray is the sensor position at that point's time.
  for (std::size_t i = 0; i < origins.size(); i += 97) {
    const Eigen::Vector3d want = (truePose(scan.view().utimeOf(i)).odomFromBody() * extrinsic()).translation();
    EXPECT_LT((origins[i] - want).norm(), 1e-9) << i;
  }
  EXPECT_EQ(deskew.lastInterpolations(), 900U) << "one interpolation per firing time";
}

TEST(Deskew, PointsPlacedWithTheScanStartPoseMissTheWall) {
  // The same scan placed without deskew (the pose at scan start for every point): the test's motion is
  // large enough to matter, so the deskew test above cannot pass by accident.
  const WallScan scan = wallScan();
  const Eigen::Isometry3d odom_from_sensor = truePose(kScanStart).odomFromBody() * extrinsic();
  double worst = 0.0;
  for (std::size_t i = 0; i < scan.x.size(); ++i) {
    const Eigen::Vector3d p(static_cast<double>(scan.x[i]), static_cast<double>(scan.y[i]),
                            static_cast<double>(scan.z[i]));
    worst = std::max(worst, std::abs((odom_from_sensor * p).x() - kWallX));
  }
  EXPECT_GT(worst, 0.1);
}

TEST(Deskew, ScanNotYetCoveredIsNotPlacedAtAll) {
  const WallScan scan = wallScan();
  const PoseBuffer poses = odometry(kScanStart - 20'000, kScanStart + 50'000);  // half the scan
  Deskew deskew(extrinsic());
  std::vector<Eigen::Vector3d> origins(3);
  std::vector<Eigen::Vector3d> endpoints(3);
  EXPECT_EQ(deskew.place(scan.view(), poses, origins, endpoints), PoseCoverage::kNotYet);
  EXPECT_TRUE(origins.empty());
  EXPECT_TRUE(endpoints.empty());
  EXPECT_EQ(deskew.lastInterpolations(), 0U);
}

TEST(Deskew, ScanOlderThanTheOldestPoseIsTooOld) {
  const WallScan scan = wallScan();
  const PoseBuffer poses = odometry(kScanStart + 10'000, kScanStart + 200'000);
  Deskew deskew(extrinsic());
  std::vector<Eigen::Vector3d> origins;
  std::vector<Eigen::Vector3d> endpoints;
  EXPECT_EQ(deskew.place(scan.view(), poses, origins, endpoints), PoseCoverage::kTooOld);
  EXPECT_TRUE(endpoints.empty());
}

TEST(Deskew, TimeSpanRunsFromTheEarliestToTheLatestPoint) {
  const std::vector<float> xyz(3, 1.0f);
  const std::vector<std::int32_t> offsets{5'000, 1'499, 99'600};
  const ScanTimeSpan span = timeSpanOf({1'000'000, xyz, xyz, xyz, offsets});
  EXPECT_EQ(span.begin_utime, 1'000'001);  // 1.499 µs rounds to 1
  EXPECT_EQ(span.end_utime, 1'000'100);    // 99.6 µs rounds to 100
}

}  // namespace
}  // namespace ogf::fusion
