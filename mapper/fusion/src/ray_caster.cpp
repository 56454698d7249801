// Set-up of the Amanatides & Woo traversal: cells, steps and the first boundary crossings.
#include <ogf/fusion/ray_caster.hpp>

#include <cmath>

namespace ogf::fusion {

RayCaster::RayCaster(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, double resolution)
    : end_cell_(cellKeyOf(endpoint, resolution)) {
  const CellKey start = cellKeyOf(origin, resolution);
  RayIterator& it = first_;
  it.cell_ = {start.x, start.y, start.z};
  const std::array<std::int32_t, 3> stop{end_cell_.x, end_cell_.y, end_cell_.z};

  // Work in cell units, with the same division cellKeyOf uses, so the first and last cells agree with it.
  std::array<double, 3> first_gap{};  // distance (cells) from the origin to its first boundary per axis
  std::array<double, 3> extent{};     // |D| per moving axis, 1 for an axis that never crosses
  for (std::size_t a = 0; a < 3; ++a) {
    const auto ai = static_cast<Eigen::Index>(a);
    const double u0 = origin[ai] / resolution;
    const double u1 = endpoint[ai] / resolution;
    const std::int64_t diff = std::int64_t{stop[a]} - std::int64_t{it.cell_[a]};
    it.left_[a] = diff < 0 ? -diff : diff;
    it.step_[a] = diff < 0 ? -1 : 1;
    if (diff > 0) it.upward_axes_ |= 1U << a;
    if (diff == 0) {
      extent[a] = 1.0;
      continue;
    }
    // A moving axis has u1 != u0 (floor is monotone), so the scaling below never multiplies by zero.
    extent[a] = std::abs(u1 - u0);
    first_gap[a] = diff > 0 ? static_cast<double>(it.cell_[a]) + 1.0 - u0 : u0 - static_cast<double>(it.cell_[a]);
  }
  // A&W's tDelta = 1/|D_a| and tMax = gap_a/|D_a|, both multiplied by the product of the |D| of the moving
  // axes: the comparisons are the same and no division rounds.
  const std::array<double, 3> scale{extent[1] * extent[2], extent[0] * extent[2], extent[0] * extent[1]};
  it.crossings_left_ = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    it.crossings_left_ += it.left_[a];
    if (it.left_[a] == 0) continue;
    it.delta_[a] = scale[a];
    it.next_[a] = first_gap[a] * scale[a];
  }
}

}  // namespace ogf::fusion
