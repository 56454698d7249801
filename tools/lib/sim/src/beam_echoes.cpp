// Beam tracing through semi-transparent surfaces.
#include "ogf/sim/beam_echoes.hpp"

#include <algorithm>
#include <cmath>

namespace ogf::sim {
namespace {

constexpr double kMinIncidenceFactor = 0.1;
// A beam that continues past a semi-transparent solid restarts this far behind its exit face.
constexpr double kExitNudge = 1e-6;
// Below this share of the emitted power nothing further is detected.
constexpr double kMinShare = 0.05;

}  // namespace

const Echo* BeamEchoes::strongest(bool excluding_last) const {
  const std::size_t n = excluding_last && count > 0 ? count - 1 : count;
  const Echo* best = nullptr;
  for (std::size_t i = 0; i < n; ++i) {
    if (best == nullptr || echoes[i].intensity > best->intensity) best = &echoes[i];
  }
  return best;
}

BeamEchoes traceBeam(const World& world, const Ray& ray, double max_range, std::optional<double> time_s) {
  BeamEchoes out;
  double t_min = 0.0;
  double share = 1.0;  // of the emitted beam still travelling
  while (out.count < BeamEchoes::kMax && share >= kMinShare) {
    const auto hit = world.firstHit(ray, t_min, max_range, time_s);
    if (!hit) break;
    const Material& m = world.materialOf(*hit);
    const double incidence = std::max(kMinIncidenceFactor, std::abs(hit->normal.dot(ray.direction)));
    out.echoes[out.count++] = Echo{hit->range, m.reflectivity * share * (1.0 - m.transmittance) * incidence};
    if (m.transmittance <= 0.0 || !std::isfinite(hit->exit)) break;
    share *= m.transmittance;
    t_min = hit->exit + kExitNudge;
  }
  return out;
}

}  // namespace ogf::sim
