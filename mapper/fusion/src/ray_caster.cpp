// Set-up of the Amanatides & Woo traversal: cells, steps and the first boundary crossings.
#include <ogf/fusion/ray_caster.hpp>

#include <cmath>

namespace ogf::fusion {
namespace {

// std::floor for |u| < 2^31, without the libm call std::floor compiles to on baseline x86-64 (no SSE4.1
// roundsd): truncation is exact, and one below it when u was negative with a fraction. Same result as
// the floor in cellKeyOf for every such double.
std::int32_t floorToInt(double u) {
  const auto t = static_cast<std::int32_t>(u);
  return static_cast<double>(t) > u ? t - 1 : t;
}

}  // namespace

RayCaster::RayCaster(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, double resolution) {
  RayIterator& it = first_;
  std::array<std::int32_t, 3> stop{};
  std::array<double, 3> first_gap{};  // distance (cells) from the origin to its first boundary per axis
  std::array<double, 3> extent{};     // |D| per moving axis, 1 for an axis that never crosses
  for (std::size_t a = 0; a < 3; ++a) {
    const auto ai = static_cast<Eigen::Index>(a);
    // Cell units by the same division and floor as cellKeyOf, so the first and last cells agree with it.
    const double u0 = origin[ai] / resolution;
    const double u1 = endpoint[ai] / resolution;
    it.cell_[a] = floorToInt(u0);
    stop[a] = floorToInt(u1);
    const std::int64_t diff = std::int64_t{stop[a]} - std::int64_t{it.cell_[a]};
    it.left_[a] = diff < 0 ? -diff : diff;
    it.step_[a] = diff < 0 ? -1 : 1;
    if (diff == 0) {
      extent[a] = 1.0;
      continue;
    }
    // A moving axis has u1 != u0 (floor is monotone), so the scaling below never multiplies by zero.
    extent[a] = std::abs(u1 - u0);
    first_gap[a] = diff > 0 ? static_cast<double>(it.cell_[a]) + 1.0 - u0 : u0 - static_cast<double>(it.cell_[a]);
  }
  end_cell_ = {stop[0], stop[1], stop[2]};
  // A&W's tDelta = 1/|D_a| and tMax = gap_a/|D_a|, both multiplied by the product of the |D| of the moving
  // axes: the comparisons are the same and no division rounds.
  const std::array<double, 3> scale{extent[1] * extent[2], extent[0] * extent[2], extent[0] * extent[1]};
  it.crossings_left_ = 0;
  for (std::size_t a = 0; a < 3; ++a) {
    it.crossings_left_ += it.left_[a];
    if (it.left_[a] == 0) continue;  // never chosen: next_ stays +inf
    it.delta_[a] = scale[a];
    it.next_[a] = first_gap[a] * scale[a];
  }
}

}  // namespace ogf::fusion
