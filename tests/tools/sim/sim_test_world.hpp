// Small worlds the ogf_sim tests fire the simulated VLP-16 into.
#pragma once

#include "ogf/sim/world.hpp"

namespace ogf::sim::test {

// Only the ground (z = 0).
inline World groundOnly() {
  World w;
  w.name = "ground";
  w.materials = {Material{"default", 50, 0}};
  w.solids = {Solid{HalfSpace{}, 0}};
  w.bounds = Aabb{{-10, -10, -1}, {10, 10, 3}};
  return w;
}

// Ground, a 1.3 m-high glass pane (reflectivity `glass_reflectivity`, transmittance 0.6) across x = 2, and
// an opaque wall (reflectivity 60) across x = 5, 4 m high.
inline World glassBeforeWall(double glass_reflectivity = 15.0) {
  World w;
  w.name = "glass";
  w.materials = {Material{"default", 50, 0}, Material{"glass", glass_reflectivity, 0.6}, Material{"wall", 60, 0}};
  w.solids = {Solid{HalfSpace{}, 0}, Solid{Box{{2.0, 0, 0.65}, {0.02, 6, 1.3}, 0}, 1},
              Solid{Box{{5.1, 0, 2.0}, {0.2, 20, 4.0}, 0}, 2}};
  w.bounds = Aabb{{-1, -10, -1}, {6, 10, 4}};
  return w;
}

}  // namespace ogf::sim::test
