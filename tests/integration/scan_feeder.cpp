#include "scan_feeder.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace ogf::testing {
namespace {

constexpr std::int64_t kStart = 1'700'000'000'000'000;  // µs
constexpr std::int64_t kScanPeriod = 100'000;

Eigen::Isometry3d bodyAt(std::int64_t utime) {
  const double t = static_cast<double>(utime - kStart) * 1e-6;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1.5 * std::cos(0.05 * t), 1.0 * std::sin(0.05 * t), 0.5);
  T.linear() = Eigen::AngleAxisd(0.1 * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

// Range along a ray from o (inside the room) to the walls x = ±5, y = ±4, floor z = 0, ceiling z = 2.
double rangeInRoom(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = std::numeric_limits<double>::infinity();
  const auto hit = [&](double p, double dp, double lim) {
    if (std::abs(dp) < 1e-12) return;
    const double t = (lim - p) / dp;
    if (t > 0 && t < best) best = t;
  };
  hit(o.x(), d.x(), 5.0);
  hit(o.x(), d.x(), -5.0);
  hit(o.y(), d.y(), 4.0);
  hit(o.y(), d.y(), -4.0);
  hit(o.z(), d.z(), 0.0);
  hit(o.z(), d.z(), 2.0);
  return best;
}

}  // namespace

FeedStep feedStep(int i, int points) {
  FeedStep step;
  const std::int64_t t0 = kStart + i * kScanPeriod;
  const std::int64_t t1 = t0 + kScanPeriod - 1000;
  // Odometry on a 10 ms grid: scan i brings the poses in (t0, t0 + 100 ms], the first one also those from
  // 20 ms before it, so every scan is covered by the time it arrives.
  const auto pushPose = [&](std::int64_t t) {
    const Eigen::Isometry3d T = bodyAt(t);
    const Eigen::Quaterniond q(T.linear());
    ogf::odometry_t o{};
    o.utime = t;
    o.frame_id = "odom";
    o.child_frame_id = "base_link";
    o.position[0] = T.translation().x();
    o.position[1] = T.translation().y();
    o.position[2] = T.translation().z();
    o.orientation[0] = q.w();
    o.orientation[1] = q.x();
    o.orientation[2] = q.y();
    o.orientation[3] = q.z();
    step.poses.push_back(o);
  };
  if (i == 0)
    for (std::int64_t t = t0 - 20'000; t <= t0; t += 10'000) pushPose(t);
  for (std::int64_t t = t0 + 10'000; t <= t0 + kScanPeriod; t += 10'000) pushPose(t);
  ogf::lidar_scan_t& s = step.scan;
  s.utime = t0;
  s.seq = i;
  s.frame_id = "velodyne";
  s.device_utime_start = t0;
  s.device_utime_end = t1;
  s.host_utime_start = t0;
  s.host_utime_end = t1;
  s.model = ogf::lidar_scan_t::MODEL_VLP16;
  s.return_mode = ogf::lidar_scan_t::RETURN_MODE_STRONGEST;
  s.rpm = 600;
  s.num_points = points;
  for (int k = 0; k < points; ++k) {
    const std::int32_t dt_ns = static_cast<std::int32_t>(static_cast<std::int64_t>(k) * (t1 - t0) * 1000 / points);
    const double az = 2 * M_PI * k / points;
    const double el = (-15.0 + 2.0 * (k % 16)) * M_PI / 180.0;
    const Eigen::Vector3d d_sensor(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    // The sensor frame is the body frame here; place the ray with the body pose at the point's time.
    const Eigen::Isometry3d T = bodyAt(t0 + dt_ns / 1000);
    const double r = rangeInRoom(T.translation(), T.linear() * d_sensor);
    const Eigen::Vector3d p = d_sensor * r;
    s.x.push_back(static_cast<float>(p.x()));
    s.y.push_back(static_cast<float>(p.y()));
    s.z.push_back(static_cast<float>(p.z()));
    s.intensity.push_back(50);
    s.ring.push_back(static_cast<std::int8_t>(k % 16));
    s.laser_id.push_back(static_cast<std::int8_t>(k % 16));
    s.azimuth_deg.push_back(static_cast<float>(az * 180 / M_PI));
    s.time_offset_ns.push_back(dt_ns);
    s.return_type.push_back(ogf::lidar_scan_t::RETURN_STRONGEST);
  }
  s.packets_expected = s.packets_received = 76;
  s.packets_lost = 0;
  return step;
}

}  // namespace ogf::testing
