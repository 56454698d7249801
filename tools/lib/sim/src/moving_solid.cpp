// Placing a moving solid at its path's pose.
#include "ogf/sim/moving_solid.hpp"

#include <cmath>

namespace ogf::sim {

Result<MovingSolid> MovingSolid::build(const MovingSolidSpec& spec) {
  if (std::holds_alternative<HalfSpace>(spec.solid.shape)) return Error{"a moving solid must be a box or a cylinder"};
  if (!std::isfinite(spec.start_s) || spec.start_s < 0.0) return Error{"start_s must be >= 0"};
  auto path = Trajectory::build(spec.path);
  if (!path) return Error{path.error().message};
  const double end = spec.path.loop || path->length() <= 0.0
                         ? std::numeric_limits<double>::infinity()
                         : spec.start_s + path->length() / spec.path.speed;
  return MovingSolid(spec.solid, std::move(*path), spec.start_s, end);
}

std::optional<Shape> MovingSolid::placedAt(double t) const {
  if (t < start_s_ || t > end_s_) return std::nullopt;
  const Pose pose = path_.poseAt(t - start_s_);
  const Eigen::Vector3d heading = pose.orientation * Eigen::Vector3d::UnitX();
  const double yaw = std::atan2(heading.y(), heading.x());
  const Eigen::Rotation2Dd turn(yaw);
  if (const auto* box = std::get_if<Box>(&solid_.shape)) {
    Box placed = *box;
    placed.centre.head<2>() = pose.position.head<2>() + turn * box->centre.head<2>();
    placed.centre.z() += pose.position.z();
    placed.yaw += yaw;
    return placed;
  }
  const auto& cyl = std::get<Cylinder>(solid_.shape);
  Cylinder placed = cyl;
  placed.centre = pose.position.head<2>() + turn * cyl.centre;
  placed.z_min += pose.position.z();
  placed.z_max += pose.position.z();
  return placed;
}

}  // namespace ogf::sim
