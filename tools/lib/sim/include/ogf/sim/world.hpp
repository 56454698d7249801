// A simulated world: materials, solids and the box the ground truth covers, plus the query the lidar model
// asks of it (the first surface a ray meets).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "ogf/sim/intersect.hpp"
#include "ogf/sim/moving_solid.hpp"
#include "ogf/sim/shapes.hpp"

namespace ogf::sim {

// An axis-aligned box [min, max], metres.
struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

// The surface a ray meets first: distance along the ray, outward normal there, which solid, and where the
// ray leaves that solid again (for semi-transparent materials).
struct SurfaceHit {
  double range = 0.0;
  double exit = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  std::size_t solid = 0;
};

struct World {
  std::string name;
  std::vector<Material> materials;  // never empty: index 0 is the default material
  std::vector<Solid> solids;
  std::vector<MovingSolid> movers;  // seen by the lidar at their time, never part of the ground truth
  Aabb bounds;  // the region the ground truth grid covers

  // The first surface the ray enters at a distance in [t_min, t_max]. A solid that already contains the
  // point at t_min is looked through (a sensor inside a solid sees out of it). With `time_s` (seconds into
  // the capture) the moving solids present then count too; their hits number from solids.size() on.
  std::optional<SurfaceHit> firstHit(const Ray& ray, double t_min, double t_max,
                                     std::optional<double> time_s = std::nullopt) const;

  const Material& materialOf(const SurfaceHit& hit) const {
    return materials[hit.solid < solids.size() ? solids[hit.solid].material
                                               : movers[hit.solid - solids.size()].material()];
  }
};

// The bounding box of a shape; nullopt for a half-space, which is unbounded.
std::optional<Aabb> boundsOf(const Shape& shape);

}  // namespace ogf::sim
