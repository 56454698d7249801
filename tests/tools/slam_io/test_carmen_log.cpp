// CarmenReader on real benchmark lines (ODOM, FLASER with the 180-degree convention, PARAM maximum range),
// a ROBOTLASER1 line in CARMEN's documented layout, malformed lines reported with source and line number
// while reading goes on, and the result record a SLAM run writes read back unchanged but for its poses.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "intel_flaser_line.hpp"
#include "ogf/slam_io/carmen_log.hpp"

namespace {

using namespace ogf::slam_io;

constexpr double kDeg = std::numbers::pi / 180.0;

// Everything a reader makes of `text`.
struct ReadLog {
  std::vector<Record> records;
  std::vector<std::string> errors;
  std::size_t lines_read = 0;
  std::size_t lines_skipped = 0;
  std::size_t lines_malformed = 0;
};

ReadLog readLog(const std::string& text) {
  std::istringstream in(text);
  CarmenReader reader(in, "test.clf");
  ReadLog log;
  while (auto r = reader.next()) {
    if (r->ok())
      log.records.push_back(r->value());
    else
      log.errors.push_back(r->error().message);
  }
  log.lines_read = reader.linesRead();
  log.lines_skipped = reader.linesSkipped();
  log.lines_malformed = reader.linesMalformed();
  return log;
}

std::vector<Record> readAll(const std::string& text) { return readLog(text).records; }

// ROBOTLASER1 in the layout CARMEN documents (fr-clinic uses it): the laser 0.05 m ahead of the robot.
const std::string kRobotLaser =
    "ROBOTLASER1 0 -1.570796 3.141593 0.785398 81.900000 0.010000 0 5 1.10 1.20 81.90 1.40 1.50 0 "
    "0.399750 1.004992 0.100000 0.350000 1.000000 0.100000 0.000000 0.000000 0.550000 0.050000 0.000000 "
    "1180.123456 clinic 0.456789";

TEST(CarmenReader, ParsesARealOdomLineWithItsStampVerbatim) {
  const auto records =
      readAll("ODOM -3.043600 8.291034 -3.122499 0.082500 -0.000151 0.000000 1214.768515 magnum 3.244480\n");
  ASSERT_EQ(records.size(), 1u);
  const auto& odom = std::get<OdometryRecord>(records[0]);
  EXPECT_DOUBLE_EQ(odom.pose.x, -3.0436);
  EXPECT_DOUBLE_EQ(odom.pose.y, 8.291034);
  EXPECT_DOUBLE_EQ(odom.pose.theta, -3.122499);
  EXPECT_DOUBLE_EQ(odom.tv, 0.0825);
  EXPECT_DOUBLE_EQ(odom.rv, -0.000151);
  EXPECT_DOUBLE_EQ(odom.stamp.ipc_timestamp, 1214.768515);
  EXPECT_EQ(odom.stamp.ipc_timestamp_text, "1214.768515");
  EXPECT_EQ(odom.stamp.ipc_hostname, "magnum");
  EXPECT_DOUBLE_EQ(odom.stamp.logger_timestamp, 3.24448);
  EXPECT_EQ(odom.line, 1u);
}

TEST(CarmenReader, ParsesARealFlaserLineWithTheHalfCircleConvention) {
  const auto records = readAll(std::string("# comment\n\n") + test_lines::kIntelFirstFlaser + "\n");
  ASSERT_EQ(records.size(), 1u);
  const auto& laser = std::get<LaserRecord>(records[0]);
  EXPECT_EQ(laser.kind, LaserRecord::Kind::kFlaser);
  ASSERT_EQ(laser.ranges.size(), 180u);
  EXPECT_FLOAT_EQ(laser.ranges.front(), 1.07f);
  EXPECT_FLOAT_EQ(laser.ranges[92], 81.83f);  // "no return"
  EXPECT_FLOAT_EQ(laser.ranges.back(), 1.05f);
  // 180 beams: -90 degrees, 1-degree steps (GMapping's CARMEN reader).
  EXPECT_NEAR(laser.start_angle, -90.0 * kDeg, 1e-12);
  EXPECT_NEAR(laser.angular_resolution, 1.0 * kDeg, 1e-12);
  EXPECT_GE(laser.ranges[92], laser.max_range);
  EXPECT_DOUBLE_EQ(laser.laser_pose.theta, -0.002458);
  EXPECT_DOUBLE_EQ(laser.robot_pose.theta, -0.002458);
  EXPECT_EQ(laser.stamp.ipc_timestamp_text, "976052857.337530");
  EXPECT_EQ(laser.line, 3u);
  EXPECT_EQ(laser.original_line, test_lines::kIntelFirstFlaser);
}

TEST(CarmenReader, FlaserResolutionFollowsTheBeamCount) {
  const auto flaser = [](int n) {
    std::string line = "FLASER " + std::to_string(n);
    for (int i = 0; i < n; ++i) line += " 1.0";
    line += " 0 0 0 0 0 0 1.0 nohost 0\n";
    return std::get<LaserRecord>(readAll(line).at(0));
  };
  EXPECT_NEAR(flaser(360).angular_resolution, 0.5 * kDeg, 1e-12);
  EXPECT_NEAR(flaser(181).angular_resolution, 1.0 * kDeg, 1e-12);
  EXPECT_NEAR(flaser(361).angular_resolution, 0.5 * kDeg, 1e-12);
  const auto wide = flaser(361);
  EXPECT_NEAR(wide.start_angle + 360 * wide.angular_resolution, 90.0 * kDeg, 1e-12);
}

TEST(CarmenReader, FlaserMaximumRangeComesFromTheFrontLaserParam) {
  const std::string line = "FLASER 2 1.0 81.91 0 0 0 0 0 0 1.0 nohost 0\n";
  EXPECT_DOUBLE_EQ(std::get<LaserRecord>(readAll(line).at(0)).max_range, kFlaserDefaultMaxRange);
  // fr079's PARAM line, verbatim.
  const auto records =
      readAll("PARAM robot_front_laser_max 80.99 1071078718.462518 merci 1071078718.462517\n" + line);
  EXPECT_DOUBLE_EQ(std::get<LaserRecord>(records.at(0)).max_range, 80.99);
}

TEST(CarmenReader, ParsesRobotLaser1WithItsOwnAngles) {
  const auto records = readAll(kRobotLaser + "\n");
  ASSERT_EQ(records.size(), 1u);
  const auto& laser = std::get<LaserRecord>(records[0]);
  EXPECT_EQ(laser.kind, LaserRecord::Kind::kRobotLaser1);
  EXPECT_DOUBLE_EQ(laser.start_angle, -1.570796);
  EXPECT_DOUBLE_EQ(laser.angular_resolution, 0.785398);
  EXPECT_DOUBLE_EQ(laser.max_range, 81.9);
  ASSERT_EQ(laser.ranges.size(), 5u);
  EXPECT_FLOAT_EQ(laser.ranges[4], 1.5f);
  EXPECT_DOUBLE_EQ(laser.laser_pose.x, 0.39975);
  EXPECT_DOUBLE_EQ(laser.robot_pose.x, 0.35);
  EXPECT_EQ(laser.stamp.ipc_timestamp_text, "1180.123456");
  EXPECT_EQ(laser.stamp.ipc_hostname, "clinic");
}

TEST(CarmenReader, AnglesAreNormalised) {
  const auto records = readAll("ODOM 0 0 3.5 0 0 0 1.0 nohost 0\n");
  EXPECT_NEAR(std::get<OdometryRecord>(records.at(0)).pose.theta, 3.5 - 2.0 * std::numbers::pi, 1e-12);
}

TEST(CarmenReader, MalformedLinesAreNamedCountedAndSkipped) {
  const std::string text =
      "ODOM 0.000000 0.000000 -0.002458 0.000000 0.000000 0.000000 976052857.337284 nohost 0.000000\n"  // 1
                                                                                                        // ok
      "ODOM 0.000000 0.000000 -0.002458 0.000000 0.000000 976052857.337284 nohost 0.000000\n"  // 2 short
      "FLASER 3 1.0 2.0 0 0 0 0 0 0 1.0 nohost 0\n"                                            // 3 count
      "FLASER 2 1.0 abc 0 0 0 0 0 0 1.0 nohost 0\n"                                            // 4 number
      "PARAM robot_frontlaser_offset 0.0 nohost 0\n"                                           // 5 skipped
      "FLASER x 1.0 0 0 0 0 0 0 1.0 nohost 0\n"                                                // 6 count
      "ODOM 0 0 nan 0 0 0 1.0 nohost 0\n"                                                      // 7 nan
      "ROBOTLASER1 0 -1.57 3.14 0.78 81.9 0.01 0 5 1.1 1.2\n"                                  // 8 short
      "FLASER 2 1.0 2.0 0 0 0 0 0 0 1.5 nohost 0\n";                                           // 9 ok
  const ReadLog log = readLog(text);
  const auto& records = log.records;
  const auto& errors = log.errors;
  EXPECT_EQ(records.size(), 2u);
  ASSERT_EQ(errors.size(), 6u);
  EXPECT_NE(errors[0].find("test.clf:2: ODOM"), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find("test.clf:3: FLASER"), std::string::npos) << errors[1];
  EXPECT_NE(errors[2].find("test.clf:4: FLASER"), std::string::npos) << errors[2];
  EXPECT_NE(errors[2].find("'abc'"), std::string::npos) << errors[2];
  EXPECT_NE(errors[3].find("test.clf:6: FLASER"), std::string::npos) << errors[3];
  EXPECT_NE(errors[4].find("test.clf:7: ODOM"), std::string::npos) << errors[4];
  EXPECT_NE(errors[5].find("test.clf:8: ROBOTLASER1"), std::string::npos) << errors[5];
  EXPECT_EQ(log.lines_read, 9u);
  EXPECT_EQ(log.lines_malformed, 6u);
  EXPECT_EQ(log.lines_skipped, 1u);
  EXPECT_DOUBLE_EQ(std::get<LaserRecord>(records[1]).stamp.ipc_timestamp, 1.5);
}

// Splits on spaces for comparing written fields.
std::vector<std::string> fieldsOf(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string f; in >> f;) out.push_back(f);
  return out;
}

TEST(WriteResultRecord, FlaserRoundTripChangesOnlyThePoses) {
  const auto original = std::get<LaserRecord>(readAll(test_lines::kIntelFirstFlaser).at(0));
  const Pose2 corrected{1.25, -2.5, 0.75};
  std::ostringstream out;
  writeResultRecord(out, original, corrected);
  ASSERT_EQ(out.str().back(), '\n');

  const auto back = std::get<LaserRecord>(readAll(out.str()).at(0));
  EXPECT_EQ(back.ranges, original.ranges);
  EXPECT_EQ(back.stamp.ipc_timestamp_text, "976052857.337530");
  for (const Pose2& p : {back.laser_pose, back.robot_pose}) {
    EXPECT_NEAR(p.x, 1.25, 1e-9);
    EXPECT_NEAR(p.y, -2.5, 1e-9);
    EXPECT_NEAR(p.theta, 0.75, 1e-9);
  }
  // Every field but the six pose fields is the original text.
  const auto a = fieldsOf(original.original_line);
  const auto b = fieldsOf(out.str());
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i >= 182 && i < 188) continue;
    EXPECT_EQ(a[i], b[i]) << "field " << i;
  }
}

TEST(WriteResultRecord, RobotLaser1KeepsTheLaserMountingOffset) {
  const auto original = std::get<LaserRecord>(readAll(kRobotLaser).at(0));
  std::ostringstream out;
  writeResultRecord(out, original, Pose2{2.0, 3.0, std::numbers::pi / 2});
  const auto back = std::get<LaserRecord>(readAll(out.str()).at(0));
  EXPECT_NEAR(back.robot_pose.x, 2.0, 1e-9);
  EXPECT_NEAR(back.robot_pose.y, 3.0, 1e-9);
  // The laser 0.05 m ahead of the robot, which now faces +y.
  EXPECT_NEAR(back.laser_pose.x, 2.0, 1e-5);
  EXPECT_NEAR(back.laser_pose.y, 3.05, 1e-5);
  EXPECT_NEAR(back.laser_pose.theta, std::numbers::pi / 2, 1e-6);
  EXPECT_EQ(back.stamp.ipc_timestamp_text, "1180.123456");
  EXPECT_EQ(back.ranges, original.ranges);
}

TEST(WriteResultRecord, ARecordWithoutItsOriginalLineIsWrittenFromItsFields) {
  LaserRecord record;
  record.ranges = {1.5f, 2.25f};
  record.stamp.ipc_timestamp = 12.5;
  record.stamp.ipc_timestamp_text = "12.500001";
  std::ostringstream out;
  writeResultRecord(out, record, Pose2{1.0, 2.0, 0.5});
  const auto back = std::get<LaserRecord>(readAll(out.str()).at(0));
  EXPECT_EQ(back.ranges, record.ranges);
  EXPECT_EQ(back.stamp.ipc_timestamp_text, "12.500001");
  EXPECT_NEAR(back.robot_pose.y, 2.0, 1e-9);
}

}  // namespace
