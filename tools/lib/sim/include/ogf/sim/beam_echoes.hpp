// What one laser beam brings back from the world: the echoes along it, nearest first. An opaque surface
// ends the beam; a semi-transparent one (Material::transmittance) returns an echo and passes the rest of
// the beam on, which is how the simulator produces real second returns for dual-return mode.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include "ogf/sim/world.hpp"

namespace ogf::sim {

struct Echo {
  double range = 0.0;      // metres along the beam
  double intensity = 0.0;  // calibrated reflectivity the sensor would report, 0..255
};

struct BeamEchoes {
  static constexpr std::size_t kMax = 4;
  std::array<Echo, kMax> echoes{};
  std::size_t count = 0;

  // The farthest echo (the "last" return) and the strongest one; with `excluding_last`, the strongest
  // other than the last (the dual-return rule when the strongest is also the last, docs/wire-format.md §5.1).
  const Echo* last() const { return count == 0 ? nullptr : &echoes[count - 1]; }
  const Echo* strongest(bool excluding_last = false) const;
};

// Echoes up to `max_range` metres. The reported intensity is the material's reflectivity scaled by the
// share of the beam that reached the surface, by what the surface returns (1 − transmittance), and by the
// cosine of the incidence angle (a Lambertian surface, floored at 0.1 so grazing hits still show).
// `time_s` (seconds into the capture) places the moving solids; without it only the static world is seen.
BeamEchoes traceBeam(const World& world, const Ray& ray, double max_range,
                     std::optional<double> time_s = std::nullopt);

}  // namespace ogf::sim
