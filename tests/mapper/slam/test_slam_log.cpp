// ogf-slam2d's log handling: odometry per laser record (ODOM interpolated to the stamp, or the record's
// own pose), the laser's offset on the robot, and a record as a planar scan.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "ogf/slam2d/slam_log.hpp"

namespace ogf::slam2d {
namespace {

std::string flaser(double lx, double ly, double lt, double rx, double ry, double rt, const char* stamp) {
  std::ostringstream s;
  s << "FLASER 3 1.0 2.0 50.0 " << lx << " " << ly << " " << lt << " " << rx << " " << ry << " " << rt << " "
    << stamp << " host 0.0\n";
  return s.str();
}

TEST(SlamLog, OdomLinesAreInterpolatedToTheLaserStamp) {
  std::istringstream in("ODOM 0 0 0 0 0 0 10.0 host 0\n" + flaser(9, 9, 0, 9, 9, 0, "10.25") +
                        "ODOM 1 0 0.2 0 0 0 11.0 host 0\n" + flaser(9, 9, 0, 9, 9, 0, "12.0"));
  const SlamLog log = readSlamLog(in, "mem");
  ASSERT_EQ(log.lasers.size(), 2U);
  ASSERT_EQ(log.odometry.size(), 2U);
  const auto odo = odometryAtLaserStamps(log, OdometrySource::kOdomLines);
  // A quarter of the way from (0,0,0) to (1,0,0.2), composed along the step.
  EXPECT_NEAR(odo[0].theta, 0.05, 1e-9);
  EXPECT_NEAR(std::hypot(odo[0].x, odo[0].y), 0.25, 0.01);
  // After the last ODOM line: that line's pose.
  EXPECT_NEAR(odo[1].x, 1.0, 1e-9);
  const auto own = odometryAtLaserStamps(log, OdometrySource::kLaserRecords);
  EXPECT_NEAR(own[0].x, 9.0, 1e-9);
}

TEST(SlamLog, LaserRecordsGiveOdometryWhenTheLogHasNoOdomLine) {
  std::istringstream in(flaser(1, 2, 0.5, 1, 2, 0.5, "1.0"));
  const SlamLog log = readSlamLog(in, "mem");
  const auto odo = odometryAtLaserStamps(log, OdometrySource::kOdomLines);
  ASSERT_EQ(odo.size(), 1U);
  EXPECT_NEAR(odo[0].y, 2.0, 1e-9);
}

TEST(SlamLog, LaserOffsetIsTheLaserPoseSeenFromTheRobot) {
  // The robot faces -x (theta = pi); the laser sits 0.04 m ahead of it, so 0.04 m further along -x.
  std::istringstream in(flaser(-3.04, 8.0, 3.14159265358979, -3.0, 8.0, 3.14159265358979, "1.0"));
  const SlamLog log = readSlamLog(in, "mem");
  const slam::Pose2 offset = laserOffset(log);
  EXPECT_NEAR(offset.x, 0.04, 1e-6);
  EXPECT_NEAR(offset.y, 0.0, 1e-6);
  const slam::PlanarScan scan = toPlanarScan(log.lasers[0], offset);
  ASSERT_EQ(scan.ranges_m.size(), 3U);
  EXPECT_TRUE(scan.isNoReturn(scan.ranges_m[2]));  // 50.0: "no return"
  EXPECT_NEAR(scan.sensor_pose.x, 0.04, 1e-6);
}

TEST(SlamLog, ForwardOdometryWhileReversingIsRepaired) {
  // ODOM says tv = -0.5 m/s, yet the laser records' odometry advances along the heading (fr079's defect).
  std::istringstream in("ODOM 0 0 0 -0.5 0 0 1.0 host 0\n" + flaser(0, 0, 0, 0, 0, 0, "1.0") +
                        flaser(0, 0, 0, 0.5, 0, 0, "2.0") + "ODOM 0 0 0 -0.5 0 0 2.0 host 0\n" +
                        flaser(0, 0, 0, 1.0, 0, 0, "3.0") + "ODOM 0 0 0 0.5 0 0 3.0 host 0\n");
  const SlamLog log = readSlamLog(in, "mem");
  std::vector<slam::Pose2> odo = odometryAtLaserStamps(log, OdometrySource::kLaserRecords);
  EXPECT_EQ(repairReversedOdometry(log, odo), 1U);
  EXPECT_NEAR(odo[1].x, -0.5, 1e-12);  // reversed
  EXPECT_NEAR(odo[2].x, 0.0, 1e-12);   // tv > 0 at 3.0: the forward step stays forward
}

TEST(SlamLog, OdometryThatReversesCorrectlyIsLeftAlone) {
  std::istringstream in("ODOM 0 0 0 -0.5 0 0 1.0 host 0\n" + flaser(0, 0, 0, 0, 0, 0, "1.0") +
                        flaser(0, 0, 0, -0.5, 0, 0, "2.0"));
  const SlamLog log = readSlamLog(in, "mem");
  std::vector<slam::Pose2> odo = odometryAtLaserStamps(log, OdometrySource::kLaserRecords);
  EXPECT_EQ(repairReversedOdometry(log, odo), 0U);
  EXPECT_NEAR(odo[1].x, -0.5, 1e-12);
}

TEST(SlamLog, MaxRecordsStopsReading) {
  std::istringstream in(flaser(0, 0, 0, 0, 0, 0, "1.0") + flaser(0, 0, 0, 0, 0, 0, "2.0") +
                        "garbage FLASER\n");
  EXPECT_EQ(readSlamLog(in, "mem", 1).lasers.size(), 1U);
}

TEST(SlamLog, MalformedLinesAreCountedAndReadingGoesOn) {
  std::istringstream in("FLASER 3 1.0 x\n" + flaser(0, 0, 0, 0, 0, 0, "2.0"));
  const SlamLog log = readSlamLog(in, "mem");
  EXPECT_EQ(log.lasers.size(), 1U);
  ASSERT_EQ(log.malformed.size(), 1U);
  EXPECT_NE(log.malformed[0].message.find("mem:1"), std::string::npos) << log.malformed[0].message;
}

}  // namespace
}  // namespace ogf::slam2d
