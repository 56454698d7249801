// The world's ray query and shape bounds.
#include "ogf/sim/world.hpp"

#include <cmath>

namespace ogf::sim {

std::optional<SurfaceHit> World::firstHit(const Ray& ray, double t_min, double t_max,
                                          std::optional<double> time_s) const {
  std::optional<SurfaceHit> best;
  double best_t = t_max;
  const auto consider = [&](const Shape& shape, std::size_t index) {
    const auto crossing = intersect(shape, ray);
    if (!crossing || crossing->t_enter < t_min || crossing->t_enter > best_t) return;
    best_t = crossing->t_enter;
    best = SurfaceHit{crossing->t_enter, crossing->t_exit, crossing->normal, index};
  };
  for (std::size_t i = 0; i < solids.size(); ++i) consider(solids[i].shape, i);
  if (time_s) {
    for (std::size_t i = 0; i < movers.size(); ++i) {
      if (const auto shape = movers[i].placedAt(*time_s)) consider(*shape, solids.size() + i);
    }
  }
  return best;
}

std::optional<Aabb> boundsOf(const Shape& shape) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    const double c = std::abs(std::cos(box->yaw));
    const double s = std::abs(std::sin(box->yaw));
    const Eigen::Vector3d half{0.5 * (c * box->size.x() + s * box->size.y()),
                               0.5 * (s * box->size.x() + c * box->size.y()), 0.5 * box->size.z()};
    return Aabb{box->centre - half, box->centre + half};
  }
  if (const auto* cyl = std::get_if<Cylinder>(&shape)) {
    return Aabb{{cyl->centre.x() - cyl->radius, cyl->centre.y() - cyl->radius, cyl->z_min},
                {cyl->centre.x() + cyl->radius, cyl->centre.y() + cyl->radius, cyl->z_max}};
  }
  return std::nullopt;
}

}  // namespace ogf::sim
