// Deskew: places every point of a moving scan with the pose of the sensor at the instant it was measured.
// A revolution takes 100 ms at 10 Hz, during which a robot at 1 m/s moves 10 cm and a turning one rotates
// several degrees; using one pose per scan smears walls. For each point, time = scan start +
// time_offset_ns; the body pose at that time comes from the PoseBuffer (lerp + slerp), and the
// sensor → body extrinsic from configuration gives the sensor pose:
//   T_odom_sensor(t) = T_odom_body(t) · T_body_sensor
// The ray origin is T_odom_sensor(t)'s translation and the endpoint T_odom_sensor(t)·p (Sun et al.
// Sec. VI-B: the ray runs from the sensor position at the time of that point). Points come in firing
// groups that share one time, so the pose is computed once per distinct time. A scan is placed whole or
// not at all: when any point's time is not covered, nothing is written and the coverage says whether to
// wait or to drop it.
#pragma once

#include <ogf/fusion/pose_buffer.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::fusion {

// The points of one scan in the sensor frame, as lidar_scan_t carries them (all spans of equal length).
struct ScanPoints {
  std::int64_t start_utime = 0;  // device_utime_start (or host_utime_start), microseconds
  std::span<const float> x, y, z;                // metres, sensor frame
  std::span<const std::int32_t> time_offset_ns;  // from start_utime, >= 0

  std::size_t size() const { return x.size(); }
  // Absolute time of point i, rounded to the microsecond the PoseBuffer works in.
  std::int64_t utimeOf(std::size_t i) const { return start_utime + (std::int64_t{time_offset_ns[i]} + 500) / 1000; }
};

// The first and last point time of a scan (start_utime for an empty one).
struct ScanTimeSpan {
  std::int64_t begin_utime = 0;
  std::int64_t end_utime = 0;
};
ScanTimeSpan timeSpanOf(const ScanPoints& points);

class Deskew {
 public:
  explicit Deskew(const Eigen::Isometry3d& body_from_sensor);

  // Resizes origins and endpoints to points.size() and fills them (odometry frame), or, when the scan's
  // time span is not covered, clears them and returns kNotYet (wait) or kTooOld (drop).
  PoseCoverage place(const ScanPoints& points, const PoseBuffer& poses, std::vector<Eigen::Vector3d>& origins,
                     std::vector<Eigen::Vector3d>& endpoints);

  // Pose interpolations done by the last place(): the number of distinct point times.
  std::size_t lastInterpolations() const { return last_interpolations_; }

 private:
  Eigen::Isometry3d body_from_sensor_;
  std::size_t last_interpolations_ = 0;
};

}  // namespace ogf::fusion
