// Reading a CARMEN log into memory and deriving per-scan odometry and planar scans from it.
#include "ogf/slam2d/slam_log.hpp"

#include <algorithm>
#include <istream>
#include <type_traits>
#include <variant>

namespace ogf::slam2d {

SlamLog readSlamLog(std::istream& in, const std::string& source_name, std::size_t max_laser_records) {
  SlamLog log;
  slam_io::CarmenReader reader(in, source_name);
  while (auto next = reader.next()) {
    if (!next->ok()) {
      log.malformed.push_back(next->error());
      continue;
    }
    std::visit(
        [&](auto&& r) {
          using T = std::decay_t<decltype(r)>;
          if constexpr (std::is_same_v<T, slam_io::LaserRecord>) {
            log.lasers.push_back(std::move(r));
          } else {
            log.odometry.push_back(std::move(r));
          }
        },
        std::move(next->value()));
    if (max_laser_records > 0 && log.lasers.size() >= max_laser_records) break;
  }
  log.lines_read = reader.linesRead();
  std::stable_sort(log.odometry.begin(), log.odometry.end(), [](const auto& a, const auto& b) {
    return a.stamp.ipc_timestamp < b.stamp.ipc_timestamp;
  });
  return log;
}

std::vector<slam::Pose2> odometryAtLaserStamps(const SlamLog& log, OdometrySource source) {
  std::vector<slam::Pose2> out;
  out.reserve(log.lasers.size());
  const auto& odom = log.odometry;
  for (const auto& laser : log.lasers) {
    if (odom.empty() || source == OdometrySource::kLaserRecords) {
      out.push_back(toSlamPose(laser.robot_pose));
      continue;
    }
    const double t = laser.stamp.ipc_timestamp;
    const auto it = std::lower_bound(odom.begin(), odom.end(), t,
                                     [](const auto& o, double s) { return o.stamp.ipc_timestamp < s; });
    if (it == odom.begin()) {
      out.push_back(toSlamPose(it->pose));
    } else if (it == odom.end()) {
      out.push_back(toSlamPose(odom.back().pose));
    } else {
      const auto& a = *std::prev(it);
      const auto& b = *it;
      const double span = b.stamp.ipc_timestamp - a.stamp.ipc_timestamp;
      const double f = span > 0.0 ? (t - a.stamp.ipc_timestamp) / span : 0.0;
      const slam::Pose2 pa = toSlamPose(a.pose);
      const slam::Pose2 d = slam::between(pa, toSlamPose(b.pose));
      out.push_back(slam::compose(pa, {f * d.x, f * d.y, f * d.theta}));
    }
  }
  return out;
}

namespace {
// Translational velocity below which a step counts as reversing, m/s; ODOM prints tv to 1 mm/s.
constexpr double kReversingTv = -0.02;
// A forward component below this is no motion, m.
constexpr double kStillStep = 1e-3;
}  // namespace

std::size_t repairReversedOdometry(const SlamLog& log, std::vector<slam::Pose2>& odometry) {
  const auto& odom = log.odometry;
  if (odom.empty() || odometry.size() != log.lasers.size() || odometry.empty()) return 0;
  std::size_t repaired = 0;
  std::vector<slam::Pose2> out(odometry.size());
  out[0] = odometry[0];
  for (std::size_t i = 1; i < odometry.size(); ++i) {
    slam::Pose2 step = slam::between(odometry[i - 1], odometry[i]);
    const double t = log.lasers[i].stamp.ipc_timestamp;
    auto it = std::lower_bound(odom.begin(), odom.end(), t,
                               [](const auto& o, double s) { return o.stamp.ipc_timestamp < s; });
    if (it == odom.end() ||
        (it != odom.begin() && t - std::prev(it)->stamp.ipc_timestamp < it->stamp.ipc_timestamp - t)) {
      it = std::prev(it);
    }
    if (it->tv < kReversingTv && step.x > kStillStep) {
      step.x = -step.x;
      step.y = -step.y;
      ++repaired;
    }
    out[i] = slam::compose(out[i - 1], step);
  }
  if (repaired > 0) odometry = std::move(out);
  return repaired;
}

slam::Pose2 laserOffset(const SlamLog& log) {
  if (log.lasers.empty()) return {};
  const auto& r = log.lasers.front();
  return slam::between(toSlamPose(r.robot_pose), toSlamPose(r.laser_pose));
}

slam::PlanarScan toPlanarScan(const slam_io::LaserRecord& record, const slam::Pose2& laser_offset) {
  slam::PlanarScan scan;
  scan.angle_min_rad = record.start_angle;
  scan.angle_increment_rad = record.angular_resolution;
  scan.max_range_m = record.max_range;
  scan.ranges_m = record.ranges;
  scan.sensor_pose = laser_offset;
  return scan;
}

}  // namespace ogf::slam2d
