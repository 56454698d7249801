// The solids a simulated world is made of: boxes (optionally yawed about z), vertical cylinders and
// half-spaces (the ground and infinite walls), each with a material that sets what the lidar reads back.
#pragma once

#include <Eigen/Core>

#include <string>
#include <variant>

namespace ogf::sim {

// What a surface returns to the lidar. Reflectivity is the VLP-16's calibrated reflectivity byte
// (0..100 diffuse, 101..255 retro-reflective; VLP-16 manual §6.2). A transmittance above 0 makes a
// semi-transparent surface (glass, mesh, foliage): it returns an echo and lets that fraction of the beam
// through to whatever is behind it, which is where the dual-return mode finds second returns.
struct Material {
  std::string name;
  double reflectivity = 50.0;
  double transmittance = 0.0;
};

// A box of full size `size` centred on `centre`, rotated by `yaw` (radians, counter-clockwise seen from
// above) about the vertical axis through its centre.
struct Box {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  double yaw = 0.0;
};

// A vertical cylinder: axis through (centre.x, centre.y), from z_min to z_max.
struct Cylinder {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.5;
  double z_min = 0.0;
  double z_max = 1.0;
};

// The solid {p : normal · p <= offset}; `normal` is a unit vector pointing out of the solid into the
// open air. The ground at height h is {normal (0,0,1), offset h}.
struct HalfSpace {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
};

using Shape = std::variant<Box, Cylinder, HalfSpace>;

// One solid of the world: a shape and the index of its material in World::materials.
struct Solid {
  Shape shape;
  std::size_t material = 0;
};

}  // namespace ogf::sim
