// The held-out test on a simulator run: see sim_held_out.hpp.
#include "ogf/eval/sim_held_out.hpp"

#include <ogf/fusion/measurement_set.hpp>
#include <ogf/pipeline/scan_mapper.hpp>

#include <unordered_set>

#include "ogf/eval/map_estimate.hpp"
#include "ogf/eval/octomap_baseline.hpp"

namespace ogf::eval {

Result<SimHeldOut> heldOutOnSimRun(const std::filesystem::path& sim_dir, const pipeline::MapperConfig& config,
                                   map_io::TimeBase time_base, const HeldOutSplit& split, bool octomap) {
  auto mapper = pipeline::ScanMapper::create(config);
  if (!mapper) return Error{"configuration: " + mapper.error().message};
  const double res = config.fusion.measurement.resolution_m;
  OctomapBaseline octo(res);
  fusion::MeasurementSet set(config.fusion.measurement);
  std::vector<Eigen::Vector3d> kept_o, kept_e, held_o, held_e;
  std::unordered_set<CellKey, CellKeyHash> measured;  // by the kept rays
  auto counts = replaySimRays(sim_dir, config, [&](std::int64_t scan, std::span<const Eigen::Vector3d> origins,
                                                   std::span<const Eigen::Vector3d> endpoints) {
    kept_o.clear();
    kept_e.clear();
    for (std::size_t i = 0; i < origins.size(); ++i) {
      auto& o = split.heldOut(scan, i) ? held_o : kept_o;
      auto& e = split.heldOut(scan, i) ? held_e : kept_e;
      o.push_back(origins[i]);
      e.push_back(endpoints[i]);
    }
    const auto ms = set.build(kept_o, kept_e);
    for (const auto& x : ms) measured.insert(x.key);
    mapper->apply(ms);
    if (octomap) octo.insert(ms);
  }, time_base);
  if (!counts) return counts.error();
  octo.finish();
  const auto& m = config.fusion.measurement;
  HeldOutScorer ogf_score(res, m.min_range_m, m.max_range_m), octo_score(res, m.min_range_m, m.max_range_m);
  const auto seen = [&](const CellKey& k) { return measured.contains(k); };
  for (std::size_t i = 0; i < held_o.size(); ++i) {
    ogf_score.add(held_o[i], held_e[i], [&](const CellKey& k) { return ogfEstimate(mapper->filter(), k); }, seen);
    if (octomap) octo_score.add(held_o[i], held_e[i], [&](const CellKey& k) { return octo.estimate(k); }, seen);
  }
  SimHeldOut out{{ogf_score.scores()}, *counts};
  if (octomap) out.scores.push_back(octo_score.scores());
  return out;
}

}  // namespace ogf::eval
