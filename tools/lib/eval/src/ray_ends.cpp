// The cells rays ended in: see ray_ends.hpp.
#include "ogf/eval/ray_ends.hpp"

namespace ogf::eval {

void markRayEnds(const sim::GroundTruth& truth, std::span<const Measurement> measurements,
                 std::vector<std::uint8_t>& ray_end) {
  for (const auto& m : measurements) {
    if (m.y != Measurement::kOccupied) continue;
    const std::int64_t ix = m.key.x - truth.min_key.x, iy = m.key.y - truth.min_key.y, iz = m.key.z - truth.min_key.z;
    if (ix < 0 || iy < 0 || iz < 0 || ix >= truth.size[0] || iy >= truth.size[1] || iz >= truth.size[2]) continue;
    ray_end[static_cast<std::size_t>(ix + truth.size[0] * (iy + truth.size[1] * iz))] = 1;
  }
}

}  // namespace ogf::eval
