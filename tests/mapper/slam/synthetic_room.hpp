// A synthetic 2-D world for the slam tests: walls as line segments (an 8 × 6 m room with a pillar, a box
// and a niche, so no pose is ambiguous) and an ideal range finder cast against them.
#pragma once

#include <cmath>
#include <limits>
#include <numbers>
#include <ogf/slam/planar_scan.hpp>
#include <ogf/slam/pose2.hpp>
#include <vector>

namespace ogf::slam::testing {

struct Segment {
  double x0, y0, x1, y1;
};

inline std::vector<Segment> roomWalls() {
  return {
      // Outer walls with a 1 m niche in the top wall.
      {0, 0, 8, 0},
      {8, 0, 8, 6},
      {8, 6, 5, 6},
      {5, 6, 5, 7},
      {5, 7, 4, 7},
      {4, 7, 4, 6},
      {4, 6, 0, 6},
      {0, 6, 0, 0},
      // A pillar and an L-shaped box.
      {2, 2, 2.4, 2},
      {2.4, 2, 2.4, 2.4},
      {2.4, 2.4, 2, 2.4},
      {2, 2.4, 2, 2},
      {5.5, 1.5, 6.5, 1.5},
      {6.5, 1.5, 6.5, 3},
      {6.5, 3, 6, 3},
      {6, 3, 6, 2},
      {6, 2, 5.5, 2},
      {5.5, 2, 5.5, 1.5},
  };
}

// Range along a ray from (ox, oy) at bearing a, or +inf when it hits nothing.
inline double castRay(const std::vector<Segment>& walls, double ox, double oy, double a) {
  const double dx = std::cos(a), dy = std::sin(a);
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : walls) {
    const double ex = s.x1 - s.x0, ey = s.y1 - s.y0;
    const double den = dx * ey - dy * ex;
    if (std::abs(den) < 1e-12) continue;
    const double wx = s.x0 - ox, wy = s.y0 - oy;
    const double t = (wx * ey - wy * ex) / den;  // along the ray
    const double u = (wx * dy - wy * dx) / den;  // along the segment
    if (t > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

// A 360° scan of `beams` beams from a sensor at the robot's origin, max range 20 m.
inline PlanarScan scanAt(const std::vector<Segment>& walls, const Pose2& robot, int beams = 360) {
  PlanarScan scan;
  scan.angle_min_rad = -std::numbers::pi;
  scan.angle_increment_rad = 2.0 * std::numbers::pi / beams;
  scan.max_range_m = 20.0;
  for (int i = 0; i < beams; ++i) {
    const double r =
        castRay(walls, robot.x, robot.y, robot.theta + scan.bearing(static_cast<std::size_t>(i)));
    scan.ranges_m.push_back(static_cast<float>(std::min(r, scan.max_range_m)));
  }
  return scan;
}

}  // namespace ogf::slam::testing
