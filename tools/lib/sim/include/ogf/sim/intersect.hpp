// Analytic ray–solid intersection for the simulator's shapes: where a ray is inside a solid, and whether
// a point is. The lidar model casts every beam through these; the tests check them against marching.
#pragma once

#include <Eigen/Core>

#include <optional>

#include "ogf/sim/shapes.hpp"

namespace ogf::sim {

// origin + t * direction, direction a unit vector, so t is a distance in metres.
struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();

  Eigen::Vector3d at(double t) const { return origin + t * direction; }
};

// The parameter interval [t_enter, t_exit] over which the ray is inside a (closed) solid, and the outward
// surface normal where it enters. t_enter is -infinity or negative when the origin is already inside;
// t_exit is +infinity for a half-space the ray never leaves.
struct Crossing {
  double t_enter = 0.0;
  double t_exit = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

// nullopt when the ray's line never meets the solid.
std::optional<Crossing> intersect(const Shape& shape, const Ray& ray);

// True when p is inside the closed solid.
bool contains(const Shape& shape, const Eigen::Vector3d& p);

}  // namespace ogf::sim
