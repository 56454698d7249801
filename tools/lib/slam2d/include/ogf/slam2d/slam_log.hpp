// A CARMEN log held in memory for one ogf-slam2d run: its laser records, the odometry pose at each laser
// record's stamp (ODOM lines interpolated to the stamp, or the records' own robot pose when the log has
// no ODOM line), and each record as the slam layer's PlanarScan.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <ogf/common/result.hpp>
#include <ogf/slam/planar_scan.hpp>
#include <ogf/slam/pose2.hpp>
#include <ogf/slam_io/carmen_log.hpp>
#include <string>
#include <vector>

namespace ogf::slam2d {

struct SlamLog {
  std::vector<slam_io::LaserRecord> lasers;
  std::vector<slam_io::OdometryRecord> odometry;  // sorted by ipc_timestamp
  std::vector<Error> malformed;                   // lines that could not be read; reading went on
  std::size_t lines_read = 0;
};

// Reads records until the end or until `max_laser_records` laser records (0: no limit).
SlamLog readSlamLog(std::istream& in, const std::string& source_name, std::size_t max_laser_records = 0);

// Where a scan's odometry pose comes from.
enum class OdometrySource {
  kOdomLines,     // ODOM lines interpolated to the laser record's ipc_timestamp
  kLaserRecords,  // the laser record's own robot pose (FLASER's odom triple, ROBOTLASER1's robot_pose)
};

// The odometry pose of every laser record, one per record: with kOdomLines, linear interpolation between
// the ODOM lines around the record's stamp (the nearest one outside their span); with kLaserRecords, or
// when the log has no ODOM line, the record's robot pose.
std::vector<slam::Pose2> odometryAtLaserStamps(const SlamLog& log, OdometrySource source);

// Repairs odometry that moves forward while the robot reverses: in fr079 every step with a negative
// ODOM tv (200 laser steps at -0.5 m/s) advances the odometry pose along its heading, which the
// ground-truth relations and the scans contradict. Each step between consecutive laser records whose
// nearest ODOM line has tv < 0 and whose translation points forward gets its translation negated; the
// poses are then chained again. Logs without ODOM lines, or without such steps, are left as they are.
// Returns the number of steps repaired.
std::size_t repairReversedOdometry(const SlamLog& log, std::vector<slam::Pose2>& odometry);

// The laser's pose on the robot, from the first record's laser pose seen from its robot pose (fr079's
// laser sits 0.04 m ahead of the robot centre; the other logs give zero).
slam::Pose2 laserOffset(const SlamLog& log);

// The record as a planar scan with the laser at `laser_offset` on the robot.
slam::PlanarScan toPlanarScan(const slam_io::LaserRecord& record, const slam::Pose2& laser_offset);

inline slam::Pose2 toSlamPose(const slam_io::Pose2& p) { return {p.x, p.y, p.theta}; }
inline slam_io::Pose2 toLogPose(const slam::Pose2& p) { return {p.x, p.y, p.theta}; }

}  // namespace ogf::slam2d
