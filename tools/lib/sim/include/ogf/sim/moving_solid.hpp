// A solid that moves through a world: a person walking through the lab, a cart crossing the street. Its
// shape is given in its own frame (origin on its path, x along its heading) and placed at the pose its path
// has reached; it appears at start_s and, on an open path, leaves the world when it reaches the last
// waypoint (it walked out through a door). The lidar sees it; the ground truth, which describes the world
// the map should converge to, does not.
#pragma once

#include <limits>
#include <optional>

#include "ogf/sim/shapes.hpp"
#include "ogf/sim/trajectory.hpp"

namespace ogf::sim {

struct MovingSolidSpec {
  Solid solid;           // a box or a cylinder in the solid's own frame
  TrajectorySpec path;   // waypoints at ground level; speed in m/s
  double start_s = 0.0;  // seconds after the capture starts
};

class MovingSolid {
 public:
  // Fails on a half-space shape or an invalid path.
  static Result<MovingSolid> build(const MovingSolidSpec& spec);

  // The shape in the world at `t` seconds, nullopt before start_s and after it left.
  std::optional<Shape> placedAt(double t) const;
  std::size_t material() const { return solid_.material; }
  double startS() const { return start_s_; }
  double endS() const { return end_s_; }  // +inf on a loop

 private:
  MovingSolid(Solid solid, Trajectory path, double start_s, double end_s)
      : solid_(std::move(solid)), path_(std::move(path)), start_s_(start_s), end_s_(end_s) {}
  Solid solid_;
  Trajectory path_;
  double start_s_ = 0.0;
  double end_s_ = std::numeric_limits<double>::infinity();
};

}  // namespace ogf::sim
