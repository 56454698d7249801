// Ray–solid intersection: the slab method for (yawed) boxes, a quadratic plus two caps for vertical
// cylinders, one division for half-spaces.
#include "ogf/sim/intersect.hpp"

#include <cmath>
#include <limits>

#include "units.hpp"

namespace ogf::sim {
namespace {

// Below this a direction component counts as parallel to a slab.
constexpr double kParallel = 1e-12;

// Narrows [t0, t1] to the slab lo <= o + t d <= hi along one axis; `axis_normal` becomes the entering
// normal when this slab sets t0. Returns false when the interval becomes empty.
bool clipSlab(double o, double d, double lo, double hi, double& t0, double& t1, int axis, int& enter_axis,
              double& enter_sign) {
  if (std::abs(d) < kParallel) {
    return o >= lo && o <= hi;
  }
  double a = (lo - o) / d;
  double b = (hi - o) / d;
  double sign = -1.0;  // entering through the low face: outward normal points to -axis
  if (a > b) {
    std::swap(a, b);
    sign = 1.0;
  }
  if (a > t0) {
    t0 = a;
    enter_axis = axis;
    enter_sign = sign;
  }
  t1 = std::min(t1, b);
  return t0 <= t1;
}

std::optional<Crossing> intersectBox(const Box& box, const Ray& ray) {
  // Most boxes are not yawed: skip the trigonometry (the hottest call of a simulation otherwise).
  const double c = box.yaw == 0.0 ? 1.0 : std::cos(box.yaw);
  const double s = box.yaw == 0.0 ? 0.0 : std::sin(box.yaw);
  // Into the box frame: rotate by -yaw about the centre.
  const Eigen::Vector3d rel = ray.origin - box.centre;
  const Eigen::Vector3d o{c * rel.x() + s * rel.y(), -s * rel.x() + c * rel.y(), rel.z()};
  const Eigen::Vector3d d{c * ray.direction.x() + s * ray.direction.y(),
                          -s * ray.direction.x() + c * ray.direction.y(), ray.direction.z()};
  const Eigen::Vector3d h = 0.5 * box.size;
  double t0 = -kInfinity;
  double t1 = kInfinity;
  int axis = 2;
  double sign = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (!clipSlab(o[i], d[i], -h[i], h[i], t0, t1, i, axis, sign)) return std::nullopt;
  }
  Eigen::Vector3d n_local = Eigen::Vector3d::Zero();
  n_local[axis] = sign;
  const Eigen::Vector3d normal{c * n_local.x() - s * n_local.y(), s * n_local.x() + c * n_local.y(),
                               n_local.z()};
  return Crossing{t0, t1, normal};
}

std::optional<Crossing> intersectCylinder(const Cylinder& cyl, const Ray& ray) {
  const double ox = ray.origin.x() - cyl.centre.x();
  const double oy = ray.origin.y() - cyl.centre.y();
  const double dx = ray.direction.x();
  const double dy = ray.direction.y();
  const double a = dx * dx + dy * dy;
  const double c = ox * ox + oy * oy - cyl.radius * cyl.radius;
  double t0 = -kInfinity;
  double t1 = kInfinity;
  bool side_enters = false;
  if (a < kParallel * kParallel) {
    if (c > 0.0) return std::nullopt;  // a vertical ray outside the circle
  } else {
    const double b = 2.0 * (ox * dx + oy * dy);
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return std::nullopt;
    const double root = std::sqrt(disc);
    t0 = (-b - root) / (2.0 * a);
    t1 = (-b + root) / (2.0 * a);
    side_enters = true;
  }
  int axis = -1;
  double sign = 1.0;
  const double before = t0;
  if (!clipSlab(ray.origin.z(), ray.direction.z(), cyl.z_min, cyl.z_max, t0, t1, 2, axis, sign)) {
    return std::nullopt;
  }
  Eigen::Vector3d normal;
  if (t0 > before || !side_enters) {
    normal = Eigen::Vector3d{0.0, 0.0, sign};
  } else {
    const Eigen::Vector3d p = ray.at(t0);
    normal = Eigen::Vector3d{p.x() - cyl.centre.x(), p.y() - cyl.centre.y(), 0.0}.normalized();
  }
  return Crossing{t0, t1, normal};
}

std::optional<Crossing> intersectHalfSpace(const HalfSpace& hs, const Ray& ray) {
  const double nd = hs.normal.dot(ray.direction);
  const double no = hs.normal.dot(ray.origin);
  if (std::abs(nd) < kParallel) {
    if (no > hs.offset) return std::nullopt;
    return Crossing{-kInfinity, kInfinity, hs.normal};
  }
  const double t = (hs.offset - no) / nd;
  if (nd < 0.0) return Crossing{t, kInfinity, hs.normal};  // heading into the solid
  return Crossing{-kInfinity, t, hs.normal};                // leaving it
}

}  // namespace

std::optional<Crossing> intersect(const Shape& shape, const Ray& ray) {
  if (const auto* box = std::get_if<Box>(&shape)) return intersectBox(*box, ray);
  if (const auto* cyl = std::get_if<Cylinder>(&shape)) return intersectCylinder(*cyl, ray);
  return intersectHalfSpace(std::get<HalfSpace>(shape), ray);
}

bool contains(const Shape& shape, const Eigen::Vector3d& p) {
  if (const auto* box = std::get_if<Box>(&shape)) {
    const Eigen::Vector3d rel = p - box->centre;
    const double c = std::cos(box->yaw);
    const double s = std::sin(box->yaw);
    const Eigen::Vector3d local{c * rel.x() + s * rel.y(), -s * rel.x() + c * rel.y(), rel.z()};
    return (local.cwiseAbs().array() <= 0.5 * box->size.array()).all();
  }
  if (const auto* cyl = std::get_if<Cylinder>(&shape)) {
    const double dx = p.x() - cyl->centre.x();
    const double dy = p.y() - cyl->centre.y();
    return dx * dx + dy * dy <= cyl->radius * cyl->radius && p.z() >= cyl->z_min && p.z() <= cyl->z_max;
  }
  const auto& hs = std::get<HalfSpace>(shape);
  return hs.normal.dot(p) <= hs.offset;
}

}  // namespace ogf::sim
