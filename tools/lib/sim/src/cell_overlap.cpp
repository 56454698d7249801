// Cell–solid overlap. Inside: every corner of the cell strictly inside the solid (enough, as solid and
// cell are convex). Otherwise Surface when the closed shapes touch, None when they do not.
#include "ogf/sim/cell_overlap.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace ogf::sim {
namespace {

std::array<Eigen::Vector3d, 8> corners(const Aabb& c) {
  std::array<Eigen::Vector3d, 8> out;
  for (std::size_t i = 0; i < 8; ++i) {
    out[i] = {(i & 1u) ? c.max.x() : c.min.x(), (i & 2u) ? c.max.y() : c.min.y(), (i & 4u) ? c.max.z() : c.min.z()};
  }
  return out;
}

CellOverlap boxOverlap(const Box& box, const Aabb& cell) {
  const double c = std::cos(box.yaw);
  const double s = std::sin(box.yaw);
  const Eigen::Vector3d h = 0.5 * box.size;
  bool all_inside = true;
  for (const auto& p : corners(cell)) {
    const Eigen::Vector3d rel = p - box.centre;
    const Eigen::Vector3d local{c * rel.x() + s * rel.y(), -s * rel.x() + c * rel.y(), rel.z()};
    all_inside = all_inside && (local.cwiseAbs().array() < h.array()).all();
  }
  if (all_inside) return CellOverlap::Inside;
  // Separating axes: z, then in the plane the cell's x and y and the box's two yawed axes (both shapes
  // are prisms over z, so these five are all there are).
  if (cell.max.z() < box.centre.z() - h.z() || cell.min.z() > box.centre.z() + h.z()) return CellOverlap::None;
  const std::array<Eigen::Vector2d, 4> axes = {Eigen::Vector2d{1, 0}, Eigen::Vector2d{0, 1}, Eigen::Vector2d{c, s},
                                               Eigen::Vector2d{-s, c}};
  const std::array<Eigen::Vector2d, 4> cell_xy = {Eigen::Vector2d{cell.min.x(), cell.min.y()},
                                                  Eigen::Vector2d{cell.max.x(), cell.min.y()},
                                                  Eigen::Vector2d{cell.min.x(), cell.max.y()},
                                                  Eigen::Vector2d{cell.max.x(), cell.max.y()}};
  const Eigen::Vector2d centre{box.centre.x(), box.centre.y()};
  const Eigen::Vector2d u{c, s};
  const Eigen::Vector2d v{-s, c};
  for (const auto& axis : axes) {
    double lo = cell_xy[0].dot(axis);
    double hi = lo;
    for (const auto& p : cell_xy) {
      lo = std::min(lo, p.dot(axis));
      hi = std::max(hi, p.dot(axis));
    }
    const double mid = centre.dot(axis);
    const double radius = h.x() * std::abs(u.dot(axis)) + h.y() * std::abs(v.dot(axis));
    if (hi < mid - radius || lo > mid + radius) return CellOverlap::None;
  }
  return CellOverlap::Surface;
}

CellOverlap cylinderOverlap(const Cylinder& cyl, const Aabb& cell) {
  if (cell.max.z() < cyl.z_min || cell.min.z() > cyl.z_max) return CellOverlap::None;
  const double nx = std::clamp(cyl.centre.x(), cell.min.x(), cell.max.x());
  const double ny = std::clamp(cyl.centre.y(), cell.min.y(), cell.max.y());
  const double r2 = cyl.radius * cyl.radius;
  if ((nx - cyl.centre.x()) * (nx - cyl.centre.x()) + (ny - cyl.centre.y()) * (ny - cyl.centre.y()) > r2) {
    return CellOverlap::None;
  }
  bool all_inside = cell.min.z() > cyl.z_min && cell.max.z() < cyl.z_max;
  for (const auto& p : corners(cell)) {
    const double dx = p.x() - cyl.centre.x();
    const double dy = p.y() - cyl.centre.y();
    all_inside = all_inside && dx * dx + dy * dy < r2;
  }
  return all_inside ? CellOverlap::Inside : CellOverlap::Surface;
}

CellOverlap halfSpaceOverlap(const HalfSpace& hs, const Aabb& cell) {
  double lo = hs.normal.dot(cell.min);
  double hi = lo;
  for (const auto& p : corners(cell)) {
    lo = std::min(lo, hs.normal.dot(p));
    hi = std::max(hi, hs.normal.dot(p));
  }
  if (hi < hs.offset) return CellOverlap::Inside;
  if (lo > hs.offset) return CellOverlap::None;
  return CellOverlap::Surface;
}

}  // namespace

CellOverlap classifyCell(const Shape& shape, const Aabb& cell) {
  if (const auto* box = std::get_if<Box>(&shape)) return boxOverlap(*box, cell);
  if (const auto* cyl = std::get_if<Cylinder>(&shape)) return cylinderOverlap(*cyl, cell);
  return halfSpaceOverlap(std::get<HalfSpace>(shape), cell);
}

}  // namespace ogf::sim
