// ogf-eval: scores an OGF map against the ground truth of a simulator run (ogf-sim's output folder), and
// an OctoMap built from the same run's rays beside it: accuracy (eq. 13 of Sun et al.), precision and
// recall of occupied, ROC AUC of the probabilities, coverage, gap filling and what moving solids left
// behind; with --held-out, how both maps predict rays they were not built from. A real static capture
// (--pcap --static) has no truth: there the scores are how each map holds its own returns, and the
// held-out test. A table on stdout; top-down PNGs, the occupied cells as PLY and the OctoMap as .bt on
// request. With --odometry/--corrected, the absolute trajectory error of those poses against the run's
// trajectory_true.csv (with or without --map). This file owns the command line, the logs and the exit
// code; the work is in ogf_eval.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>
#include <unordered_set>
#include <vector>

#include <ogf/filter/map_queries.hpp>
#include <ogf/fusion/measurement_set.hpp>
#include <ogf/pipeline/scan_mapper.hpp>
#include <ogf/sim/ground_truth.hpp>
#include <ogf/sim/pose_files.hpp>
#include <ogf/transport/logging.hpp>

#include "ogf/common/command_line.hpp"
#include "ogf/eval/held_out.hpp"
#include "ogf/eval/map_scores.hpp"
#include "ogf/eval/octomap_baseline.hpp"
#include "ogf/eval/return_scores.hpp"
#include "ogf/eval/sim_measurements.hpp"
#include "ogf/eval/topdown_figures.hpp"
#include "ogf/eval/trajectory_error.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/topdown_png.hpp"

namespace {

namespace fs = std::filesystem;
namespace ev = ogf::eval;

using ogf::cli::kExitOk;
constexpr int kExitFailed = 1;  // an input could not be read, or an output not written
using ogf::cli::kExitUsage;  // bad flags or configuration

struct Column {
  std::string name;
  ev::MapScores scores;
  std::int64_t occupied_cells = 0;  // classified occupied, inside the truth grid
  std::int64_t free_cells = 0;
  std::string map_cells;            // cells the map holds, as text
  std::optional<ev::SweptScores> swept;
};

void printTable(const std::vector<Column>& cols, bool gaps) {
  std::printf("%-34s", "metric");
  for (const auto& c : cols) std::printf(" %12s", c.name.c_str());
  std::printf("\n");
  const auto row = [&](const char* label, auto get) {
    std::printf("%-34s", label);
    for (const auto& c : cols) std::printf(" %12s", get(c).c_str());
    std::printf("\n");
  };
  const auto f4 = [](double v) { return fmt::format("{:.4f}", v); };
  const auto i64 = [](std::int64_t v) { return fmt::format("{}", v); };
  row("known truth cells (free+occupied)", [&](const Column& c) { return i64(c.scores.known); });
  row("accuracy (eq. 13, unknown = wrong)", [&](const Column& c) { return f4(c.scores.accuracy); });
  row("precision (occupied)", [&](const Column& c) { return f4(c.scores.precision); });
  row("recall (occupied)", [&](const Column& c) { return f4(c.scores.recall); });
  row("ROC AUC (probability)", [&](const Column& c) { return f4(c.scores.auc); });
  row("coverage (known cells classified)", [&](const Column& c) { return f4(c.scores.coverage); });
  if (gaps) {
    row("gap cells (truth occ., no ray end)", [&](const Column& c) { return i64(c.scores.gap_cells); });
    row("gap cells classified occupied", [&](const Column& c) { return i64(c.scores.gap_filled); });
    row("gap filling (share)", [&](const Column& c) { return f4(c.scores.gap_fill); });
    row("filled wrongly (truth free)", [&](const Column& c) { return i64(c.scores.false_filled); });
  }
  if (!cols.empty() && cols.front().swept) {
    row("moving solid: swept free cells", [&](const Column& c) { return i64(c.swept->cells); });
    row("... left occupied", [&](const Column& c) { return i64(c.swept->left_occupied); });
  }
  row("occupied cells (in truth grid)", [&](const Column& c) { return i64(c.occupied_cells); });
  row("free cells (in truth grid)", [&](const Column& c) { return i64(c.free_cells); });
  row("correct cells", [&](const Column& c) { return i64(c.scores.correct); });
  row("cells held by the map", [&](const Column& c) { return c.map_cells; });
}

template <class Estimate>
std::vector<ev::CellEstimate> classifyTruth(const ogf::sim::GroundTruth& truth, Estimate estimate) {
  std::vector<ev::CellEstimate> out(truth.cells.size());
  for (std::size_t i = 0; i < truth.cells.size(); ++i) {
    if (truth.cells[i] == static_cast<std::uint8_t>(ogf::sim::CellClass::Unobservable)) continue;
    out[i] = estimate(truth.keyOf(i));
  }
  return out;
}

Column makeColumn(std::string name, const ogf::sim::GroundTruth& truth, const std::vector<ev::CellEstimate>& est,
                  const std::vector<std::uint8_t>& ray_end, std::string map_cells) {
  Column c{std::move(name), ev::scoreMap(truth.cells, est, ray_end), 0, 0, std::move(map_cells), std::nullopt};
  for (const auto& e : est) {
    c.occupied_cells += e.cell_class > 0 ? 1 : 0;
    c.free_cells += e.cell_class < 0 ? 1 : 0;
  }
  return c;
}

// One row per given trajectory file: its ATE against the run's true trajectory. False when a file is
// unreadable or no pose of it matches the truth's stamps.
bool printTrajectoryErrors(const std::string& truth_dir,
                           const std::vector<std::pair<std::string, std::string>>& trajectories) {
  const std::string truth_path = (fs::path(truth_dir) / "trajectory_true.csv").string();
  auto truth = ogf::sim::readPoseCsv(truth_path);
  if (!truth) {
    spdlog::error("--truth: {}", truth.error().message);
    return false;
  }
  std::printf("\nabsolute trajectory error, position (m), against %s; no alignment (the odometry frame starts on "
              "the true pose)\n",
              truth_path.c_str());
  std::printf("%-34s %8s %12s %12s %12s\n", "trajectory", "poses", "RMSE", "mean", "max");
  bool ok = true;
  for (const auto& [label, path] : trajectories) {
    auto poses = ogf::sim::readPoseCsv(path);
    if (!poses) {
      spdlog::error("{}", poses.error().message);
      ok = false;
      continue;
    }
    const auto e = ev::absoluteTrajectoryError(*truth, *poses);
    if (e.unmatched > 0) {
      spdlog::warn("{}: {} of {} poses fall outside the true trajectory's stamps and are not scored", path,
                   e.unmatched, poses->size());
    }
    if (e.matched == 0) {
      spdlog::error("{}: no pose matches a stamp of {}", path, truth_path);
      ok = false;
      continue;
    }
    std::printf("%-34s %8zu %12.4f %12.4f %12.4f\n", label.c_str(), e.matched, e.rmse_m, e.mean_m, e.max_m);
  }
  return ok;
}

ev::CellEstimate ogfEstimate(const ogf::filter::BandedOgf& map, const ogf::CellKey& k) {
  const auto q = ogf::filter::queryCell(map, k);
  return ev::CellEstimate{q.occupancyClass, q.predictiveProbability};
}

void printPairTable(const std::string& title, const std::vector<std::string>& names,
                    const std::vector<std::pair<std::string, std::vector<std::string>>>& rows) {
  std::printf("\n%s\n%-34s", title.c_str(), "metric");
  for (const auto& n : names) std::printf(" %12s", n.c_str());
  std::printf("\n");
  for (const auto& [label, values] : rows) {
    std::printf("%-34s", label.c_str());
    for (const auto& v : values) std::printf(" %12s", v.c_str());
    std::printf("\n");
  }
}

void printHeldOut(const ev::HeldOutSplit& split, std::uint64_t seed, const std::vector<std::string>& names,
                  const std::vector<ev::HeldOutScores>& scores) {
  const auto col = [&](auto get) {
    std::vector<std::string> v;
    for (const auto& s : scores) v.push_back(get(s));
    return v;
  };
  printPairTable(fmt::format("held-out rays: maps built from the other rays ({:.0f} % held out of every scan, seed {})",
                             100.0 * split.share(), seed),
                 names,
                 {{"held-out rays", col([](const ev::HeldOutScores& s) { return fmt::format("{}", s.rays); })},
                  {"end cells / crossed cells", col([](const ev::HeldOutScores& s) {
                     return fmt::format("{}/{}", s.positives, s.negatives);
                   })},
                  {"held-out ROC AUC", col([](const ev::HeldOutScores& s) { return fmt::format("{:.4f}", s.auc); })},
                  {"end cells classed occupied", col([](const ev::HeldOutScores& s) {
                     return fmt::format("{:.4f}", s.positives_occupied);
                   })},
                  {"crossed cells classed free", col([](const ev::HeldOutScores& s) {
                     return fmt::format("{:.4f}", s.negatives_free);
                   })},
                  {"unseen cells: end / crossed", col([](const ev::HeldOutScores& s) {
                     return fmt::format("{}/{}", s.unseen.positives, s.unseen.negatives);
                   })},
                  {"unseen cells: ROC AUC", col([](const ev::HeldOutScores& s) {
                     return fmt::format("{:.4f}", s.unseen.auc);
                   })}});
}

// Says once that odometry and scans are on different clocks when no scan could be placed.
void reportClocks(const ev::SimMeasurementCounts& counts) {
  if (counts.scans_measured == 0 && !counts.clock_mismatch.empty()) spdlog::warn("clocks: {}", counts.clock_mismatch);
}

// The held-out test on a simulator run: an OGF (through `config`, the daemon's pipeline) and an OctoMap
// built from the rays the split keeps, scored on the rest.
ogf::Result<std::vector<ev::HeldOutScores>> heldOutOnSimRun(const std::string& truth_dir,
                                                           const ogf::pipeline::MapperConfig& config,
                                                           ogf::map_io::TimeBase time_base,
                                                           const ev::HeldOutSplit& split, bool octomap) {
  auto mapper = ogf::pipeline::ScanMapper::create(config);
  if (!mapper) return ogf::Error{"configuration: " + mapper.error().message};
  const double res = config.fusion.measurement.resolution_m;
  ev::OctomapBaseline octo(res);
  ogf::fusion::MeasurementSet set(config.fusion.measurement);
  std::vector<Eigen::Vector3d> kept_o, kept_e, held_o, held_e;
  std::unordered_set<ogf::CellKey, ogf::CellKeyHash> measured;  // by the kept rays
  auto counts = ev::replaySimRays(truth_dir, config, [&](std::int64_t scan, std::span<const Eigen::Vector3d> origins,
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
  reportClocks(*counts);
  octo.finish();
  const auto& m = config.fusion.measurement;
  ev::HeldOutScorer ogf_score(res, m.min_range_m, m.max_range_m), octo_score(res, m.min_range_m, m.max_range_m);
  const auto seen = [&](const ogf::CellKey& k) { return measured.contains(k); };
  for (std::size_t i = 0; i < held_o.size(); ++i) {
    ogf_score.add(held_o[i], held_e[i], [&](const ogf::CellKey& k) { return ogfEstimate(mapper->filter(), k); }, seen);
    if (octomap) octo_score.add(held_o[i], held_e[i], [&](const ogf::CellKey& k) { return octo.estimate(k); }, seen);
  }
  std::vector<ev::HeldOutScores> out{ogf_score.scores()};
  if (octomap) out.push_back(octo_score.scores());
  return out;
}

// A real capture of a sensor that did not move: both maps built from its returns (the OGF through
// `config`, OctoMap through its own insertPointCloud), scored on how they hold those returns; with a split,
// also built from the kept rays and scored on the held-out ones.
int evaluateStaticCapture(const std::string& pcap, const std::string& calib, const ogf::pipeline::MapperConfig& config,
                          const std::optional<ev::HeldOutSplit>& split, std::uint64_t seed) {
  namespace mio = ogf::map_io;
  mio::PcapScanConfig pc;
  pc.min_range_m = config.fusion.measurement.min_range_m;
  if (!calib.empty()) pc.calibration = calib;
  const Eigen::Isometry3d body_from_sensor = config.fusion.extrinsic.bodyFromSensor();
  const Eigen::Vector3d origin = body_from_sensor.translation();
  std::vector<std::vector<Eigen::Vector3d>> scans;
  auto read = mio::readPcapScans(pcap, pc, [&](const mio::ScanRecord& scan) {
    std::vector<Eigen::Vector3d> points(scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) points[i] = body_from_sensor * Eigen::Vector3d(scan.x[i], scan.y[i], scan.z[i]);
    scans.push_back(std::move(points));
  });
  if (!read) {
    spdlog::error("--pcap: {}", read.error().message);
    return kExitFailed;
  }
  if (!read->warning.empty()) spdlog::warn("--pcap: {}", read->warning);
  spdlog::info("calibration: {}", read->calibration);
  const auto& m = config.fusion.measurement;
  const double res = m.resolution_m;
  spdlog::info("{}: {} scans, {} points; resolution {} m, range {}-{} m", pcap, scans.size(), read->points, res,
               m.min_range_m, m.max_range_m);

  struct Maps {
    ogf::pipeline::ScanMapper ogf;
    ev::OctomapBaseline octo;
    std::unordered_set<ogf::CellKey, ogf::CellKeyHash> measured;  // cells the OGF's measurements named
  };
  const auto build = [&](const std::function<bool(std::int64_t, std::size_t)>& keep) -> ogf::Result<Maps> {
    auto mapper = ogf::pipeline::ScanMapper::create(config);
    if (!mapper) return ogf::Error{"configuration: " + mapper.error().message};
    Maps maps{std::move(*mapper), ev::OctomapBaseline(res), {}};
    ogf::fusion::MeasurementSet set(m);
    std::vector<Eigen::Vector3d> origins, points, cloud;
    for (std::size_t s = 0; s < scans.size(); ++s) {
      points.clear();
      cloud.clear();
      for (std::size_t i = 0; i < scans[s].size(); ++i) {
        if (!keep(static_cast<std::int64_t>(s), i)) continue;
        points.push_back(scans[s][i]);
        if ((scans[s][i] - origin).norm() >= m.min_range_m) cloud.push_back(scans[s][i]);
      }
      origins.assign(points.size(), origin);
      const auto ms = set.build(origins, points);
      for (const auto& x : ms) maps.measured.insert(x.key);
      maps.ogf.apply(ms);
      maps.octo.insertCloud(cloud, origin, m.max_range_m);
    }
    maps.octo.finish();
    return maps;
  };

  auto full = build([](std::int64_t, std::size_t) { return true; });
  if (!full) {
    spdlog::error("{}", full.error().message);
    return kExitFailed;
  }
  // Returns inside the mapped range with a margin: 0.1 m beyond min range, 1 m short of max range.
  const double from = std::max(m.min_range_m + 0.1, 0.5);
  const double to = m.max_range_m - 1.0;
  ev::ReturnScorer ogf_returns(res, from, to), octo_returns(res, from, to);
  for (const auto& scan : scans) {
    for (const auto& p : scan) {
      ogf_returns.add(origin, p, [&](const ogf::CellKey& k) { return ogfEstimate(full->ogf.filter(), k); });
      octo_returns.add(origin, p, [&](const ogf::CellKey& k) { return full->octo.estimate(k); });
    }
  }
  const std::vector<ev::ReturnScores> r{ogf_returns.scores(), octo_returns.scores()};
  const auto col = [&](auto get) {
    std::vector<std::string> v;
    for (const auto& x : r) v.push_back(fmt::format("{:.4f}", get(x)));
    return v;
  };
  printPairTable(fmt::format("the capture's own returns ({:.1f}-{:.1f} m), both maps built from every return; "
                             "OctoMap through insertPointCloud",
                             from, to),
                 {"OGF", "OctoMap"},
                 {{"returns", {fmt::format("{}", r[0].returns), fmt::format("{}", r[1].returns)}},
                  {"return cells classed occupied", col([](const ev::ReturnScores& x) { return x.occupied; })},
                  {"return cells classed free", col([](const ev::ReturnScores& x) { return x.free; })},
                  {"return cells unknown", col([](const ev::ReturnScores& x) { return x.unknown; })},
                  {"half-way points classed free", col([](const ev::ReturnScores& x) { return x.halfway_free; })},
                  {"cells held by the map", {fmt::format("{}", full->ogf.filter().allocatedCells()),
                                             fmt::format("{} leaves", full->octo.leafCount())}}});
  if (split) {
    auto kept = build([&](std::int64_t s, std::size_t i) { return !split->heldOut(s, i); });
    if (!kept) {
      spdlog::error("{}", kept.error().message);
      return kExitFailed;
    }
    ev::HeldOutScorer ogf_held(res, m.min_range_m, m.max_range_m), octo_held(res, m.min_range_m, m.max_range_m);
    const auto seen = [&](const ogf::CellKey& k) { return kept->measured.contains(k); };
    for (std::size_t s = 0; s < scans.size(); ++s) {
      for (std::size_t i = 0; i < scans[s].size(); ++i) {
        if (!split->heldOut(static_cast<std::int64_t>(s), i)) continue;
        ogf_held.add(origin, scans[s][i], [&](const ogf::CellKey& k) { return ogfEstimate(kept->ogf.filter(), k); }, seen);
        octo_held.add(origin, scans[s][i], [&](const ogf::CellKey& k) { return kept->octo.estimate(k); }, seen);
      }
    }
    printHeldOut(*split, seed, {"OGF", "OctoMap"}, {ogf_held.scores(), octo_held.scores()});
  }
  return kExitOk;
}


}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Scores an OGF map against the ground truth of an ogf-sim run, with an OctoMap built from the same rays "
      "beside it.\n"
      "Truth cells: free or occupied are known; unobservable ones are left out. A map cell is classified by eq. (3) "
      "(Phi(m) > r_o occupied, < r_f free, else unknown); a cell the map never allocated is unknown with p = 0.5.\n"
      "  accuracy   eq. (13): share of known cells classified as their truth; UNKNOWN COUNTS AS WRONG\n"
      "  precision, recall   of occupied over the known cells\n"
      "  ROC AUC    predictive occupancy probability, truth-occupied vs truth-free cells, ties half\n"
      "  coverage   share of known cells classified (not unknown)\n"
      "  gap filling   truth-occupied cells in which no ray of the run ended (no occupied measurement in any\n"
      "             scan, recomputed by ray casting the run's capture with its odometry), and the share of them\n"
      "             the map classifies occupied\n"
      "OctoMap: an OcTree at the map's resolution fed the same per-scan measurements (misses along each ray, a hit\n"
      "at its end; default sensor model 0.7/0.4, clamping 0.12/0.97); a node is occupied when p > 0.5 (OctoMap's own\n"
      "threshold), free otherwise, a cell without a node unknown. --octomap FILE.bt scores a given tree instead.\n"
      "Trajectories: --odometry and --corrected (CSV utime,x,y,z,qw,qx,qy,qz, e.g. the run's odometry.csv and a\n"
      "pose-corrected trajectory) are scored against the run's trajectory_true.csv: the absolute trajectory error\n"
      "(position RMSE, mean, max; the truth interpolated to each pose's stamp), without alignment since both start on\n"
      "the true pose. --map may then be left out.\n"
      "Without --map (and without --odometry/--corrected), the OGF is built here from the run's rays through the\n"
      "mapping pipeline with --config's settings (ogf-mapper's configuration file, as ogf-map reads it; --time or\n"
      "its time_base names the odometry's clock), as ogf-map would build it.\n"
      "Moving solids: when the run has swept.grid (ogf-sim --movers), the swept cells free in the truth and how many\n"
      "of them each map still classes occupied (what the moving solid left behind).\n"
      "--held-out: both maps are built again from the rays the split keeps (a hash of scan, ray and --seed below\n"
      "--held-out-share holds a ray out) and asked about the rest: each held-out ray's end cell should be occupied,\n"
      "the cells it crossed free; the ROC AUC of the predictive probability over those cells (bins of 1e-4, ties\n"
      "half) and the shares classed right; the same AUC over the cells no kept ray measured (\"unseen\": there\n"
      "OctoMap can only answer 0.5, the OGF infers from the neighbours).\n"
      "A real static capture: --pcap FILE --static [--calib FILE] instead of --truth. Both maps are built from its\n"
      "returns (OctoMap through OcTree::insertPointCloud, sensor at the origin): the share of returns (0.1 m beyond\n"
      "min range to 1 m short of max range) whose cell each map classes occupied, free or unknown, and of points\n"
      "half-way along each return classed free; with --held-out also the held-out test.\n"
      "Exit 0 when scored, 1 when an input is unreadable or an output failed, 2 on bad flags."};
  std::string map_path, truth_dir, png_dir, octomap_in, octomap_out, ply_out, log_level = "info";
  std::string odometry_path, corrected_path, config_path, pcap, calib, time_base;
  double max_range = 30.0, min_range = 0.4, resolution = 0.2, held_out_share = 0.1;
  std::uint64_t seed = 1;
  bool held_out = false, is_static = false;
  bool no_octomap = false;
  std::optional<double> png_zmin, png_zmax;  // default: the walls' band of the truth
  int scale = 1;
  app.add_option("--map", map_path,
                 "OGF map: a map file (ogf-map --out) or a daemon snapshot (snapshot.ogfs); required unless "
                 "--odometry or --corrected is given")
      ->check(CLI::ExistingFile);
  auto* truth_opt =
      app.add_option("--truth", truth_dir, "ogf-sim output folder (truth.grid, capture.pcap, odometry.csv, sim.yaml)")
          ->check(CLI::ExistingDirectory);
  auto* pcap_opt = app.add_option("--pcap", pcap, "A real capture of a sensor that did not move (with --static)")
                       ->check(CLI::ExistingFile)->excludes(truth_opt);
  app.add_flag("--static", is_static, "The --pcap sensor did not move: every ray from the sensor at the origin")
      ->needs(pcap_opt);
  app.add_option("--calib", calib, "Calibration for --pcap: VeloView XML or ROS YAML")->needs(pcap_opt)->check(CLI::ExistingFile);
  app.add_option("--config", config_path,
                 "ogf-mapper's configuration file (map, filter, fusion, time_base, pose_source) for the maps built "
                 "here: without --map, with --pcap, and for --held-out without --map; flags override it")
      ->check(CLI::ExistingFile);
  auto* time_opt = app.add_option("--time", time_base,
                                  "Clock the run's odometry is on: auto, device or host (see ogf-map --time); "
                                  "default: the config's time_base, else auto")
                       ->check(CLI::IsMember({"auto", "device", "host"}));
  auto* res_opt = app.add_option("--resolution", resolution, "Cell size of the maps built here (without --map), metres")
                      ->capture_default_str();
  app.add_flag("--held-out", held_out, "Also score both maps on rays held out of them (see above)");
  app.add_option("--held-out-share", held_out_share, "Share of every scan's rays held out")
      ->capture_default_str()->check(ogf::cli::between(0.01, 0.5));
  app.add_option("--seed", seed, "Seed of the held-out split")->capture_default_str();
  app.add_option("--png", png_dir, "Folder for truth.png, ogf_/octomap_classes.png, ogf_/octomap_errors.png and the "
                                   "map's occupancy.png/entropy.png");
  app.add_option("--png-zmin", png_zmin, "Bottom of the PNGs' height band, metres (default: the truth's walls' band)");
  app.add_option("--png-zmax", png_zmax, "Top of the PNGs' height band, metres (default: the truth's walls' band)");
  app.add_option("--png-scale", scale, "Least pixels per cell in the truth/class/error PNGs (they are at least 800 px wide or high)")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 32));
  auto* oin = app.add_option("--octomap", octomap_in, "Score this OctoMap (.bt) instead of building one")->check(CLI::ExistingFile);
  app.add_flag("--no-octomap", no_octomap, "Score the OGF only")->excludes(oin);
  app.add_option("--write-octomap", octomap_out, "Write the OctoMap built from the run as .bt");
  app.add_option("--export-ply", ply_out, "Write the OGF map's occupied cells as PLY");
  auto* max_opt = app.add_option("--max-range", max_range, "Ray cut for the recomputed measurements (use the mapper's), metres")->capture_default_str();
  auto* min_opt = app.add_option("--min-range", min_range, "Minimum range for the recomputed measurements, metres")->capture_default_str();
  app.add_option("--odometry", odometry_path, "Raw odometry poses to score (CSV, e.g. the run's odometry.csv)")
      ->check(CLI::ExistingFile);
  app.add_option("--corrected", corrected_path, "Corrected poses to score (CSV utime,x,y,z,qw,qx,qy,qz)")
      ->check(CLI::ExistingFile);
  app.add_option("--log-level", log_level, "trace|debug|info|warn|error")->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  if (!ogf::transport::setupLoggingAt("ogf-eval", "--log-level", log_level)) return kExitUsage;

  // The settings of the maps built here; --map's own filter settings replace the filter part below.
  ogf::mapper_daemon::MapperOptions file;  // the defaults when there is no --config
  if (!config_path.empty()) {
    auto read = ogf::map_io::readOfflineConfig(config_path, ogf::mapper_daemon::kUsedByEval);
    if (!read) {
      spdlog::error("--config: {}", read.error().message);
      return ogf::cli::exitCodeFor(read.error());
    }
    if (const auto note = read->unusedNote("ogf-eval"); !note.empty()) spdlog::info("--config: {}", note);
    file = read->options;
  }
  ogf::pipeline::MapperConfig built = file.map;
  const ogf::map_io::TimeBase clock = time_opt->count() == 0 ? file.time_base
                                      : time_base == "host"  ? ogf::map_io::TimeBase::kHost
                                      : time_base == "device" ? ogf::map_io::TimeBase::kDevice
                                                              : ogf::map_io::TimeBase::kAuto;
  if (file.pose_source == ogf::mapper_daemon::PoseSource::kStatic) is_static = true;
  if (config_path.empty() || res_opt->count() > 0) built.setResolution(resolution);
  if (config_path.empty() || max_opt->count() > 0) built.fusion.measurement.max_range_m = max_range;
  if (config_path.empty() || min_opt->count() > 0) built.fusion.measurement.min_range_m = min_range;
  if (auto st = built.validate(); !st) {
    spdlog::error("configuration: {}", st.error().message);
    return ogf::cli::exitCodeFor(st.error());
  }
  std::optional<ev::HeldOutSplit> split;
  if (held_out) split.emplace(held_out_share, seed);

  if (!pcap.empty()) {
    if (!is_static) {
      std::fprintf(stderr, "--pcap needs --static (a capture with odometry is scored through an ogf-sim run)\n");
      return kExitUsage;
    }
    return evaluateStaticCapture(pcap, calib, built, split, seed);
  }
  if (truth_dir.empty()) {
    std::fprintf(stderr, "--truth DIR (an ogf-sim run) or --pcap FILE --static is required\nRun with --help for more "
                         "information.\n");
    return kExitUsage;
  }

  std::vector<std::pair<std::string, std::string>> trajectories;
  if (!odometry_path.empty()) trajectories.emplace_back("odometry (raw)", odometry_path);
  if (!corrected_path.empty()) trajectories.emplace_back("corrected", corrected_path);
  if (map_path.empty() && !trajectories.empty()) return printTrajectoryErrors(truth_dir, trajectories) ? kExitOk : kExitFailed;

  auto truth = ogf::sim::readGroundTruth((fs::path(truth_dir) / "truth.grid").string());
  if (!truth) {
    spdlog::error("--truth: {}", truth.error().message);
    return kExitFailed;
  }
  // The map scored: --map, or one built here from the run's rays (in the replay below).
  std::optional<ogf::map_formats::LoadedMap> loaded;
  std::optional<ogf::pipeline::ScanMapper> own;
  ogf::pipeline::MapperConfig config = built;
  if (!map_path.empty()) {
    auto l = ogf::map_formats::loadOgfMap(map_path);
    if (!l) {
      spdlog::error("--map: {}", l.error().message);
      return kExitFailed;
    }
    loaded.emplace(std::move(*l));
    config.filter = loaded->map.config();
    config.setResolution(loaded->map.config().resolution);
  } else {
    auto m = ogf::pipeline::ScanMapper::create(config);
    if (!m) {
      spdlog::error("configuration: {}", m.error().message);
      return ogf::cli::exitCodeFor(m.error());
    }
    own.emplace(std::move(*m));
  }
  const double res = config.filter.resolution;
  if (std::abs(res - truth->resolution) > 1e-9) {
    spdlog::error("the map's resolution {} m differs from the truth's {} m: cells would not line up", res, truth->resolution);
    return kExitFailed;
  }

  // The run's measurements, recomputed: where rays ended (gap filling), the OctoMap's input, and the OGF's
  // when it is built here.
  std::vector<std::uint8_t> ray_end;
  std::optional<ev::OctomapBaseline> octo;
  bool gaps = false;
  if (!no_octomap && !octomap_in.empty()) {
    auto bt = ev::OctomapBaseline::load(octomap_in);
    if (!bt) {
      spdlog::error("--octomap: {}", bt.error().message);
      return kExitFailed;
    }
    octo.emplace(std::move(*bt));
  } else if (!no_octomap) {
    octo.emplace(res);
  }
  if (auto extr = ev::readSimExtrinsic(truth_dir); !extr) {
    if (own) {
      spdlog::error("{}: the map cannot be built from the run without it", extr.error().message);
      return kExitFailed;
    }
    spdlog::warn("{}; gap filling not scored{}", extr.error().message, octo && octomap_in.empty() ? ", no OctoMap" : "");
    if (octomap_in.empty()) octo.reset();
  } else {
    config.fusion.extrinsic = *extr;
    ray_end.assign(truth->cells.size(), 0);
    const bool build = octo && octomap_in.empty();
    auto counts = ev::replaySimMeasurements(truth_dir, config, [&](std::span<const ogf::Measurement> ms) {
      for (const auto& m : ms) {
        if (m.y != ogf::Measurement::kOccupied) continue;
        const std::int64_t ix = m.key.x - truth->min_key.x, iy = m.key.y - truth->min_key.y, iz = m.key.z - truth->min_key.z;
        if (ix < 0 || iy < 0 || iz < 0 || ix >= truth->size[0] || iy >= truth->size[1] || iz >= truth->size[2]) continue;
        ray_end[static_cast<std::size_t>(ix + truth->size[0] * (iy + truth->size[1] * iz))] = 1;
      }
      if (build) octo->insert(ms);
      if (own) own->apply(ms);
    }, clock);
    if (!counts && own) {
      spdlog::error("building the map from the run: {}", counts.error().message);
      return kExitFailed;
    }
    if (!counts) {
      spdlog::warn("recomputing the run's measurements: {}; gap filling not scored", counts.error().message);
      ray_end.clear();
      if (build) octo.reset();
    } else {
      gaps = true;
      if (build) octo->finish();
      reportClocks(*counts);
      spdlog::info("{}: {} scans, {} measured, {} measurements recomputed", truth_dir, counts->scans,
                   counts->scans_measured, counts->measurements);
    }
  }

  const ogf::filter::BandedOgf& map = own ? own->filter() : loaded->map;
  spdlog::info("{}: {}, {} cells at {} m; truth {}x{}x{} ({} occupied, {} free)",
               own ? truth_dir : map_path, own ? std::string("built from the run") : fmt::format("{} at seq {}", loaded->kind, loaded->seq),
               map.allocatedCells(), res, truth->size[0], truth->size[1], truth->size[2],
               truth->count(ogf::sim::CellClass::Occupied), truth->count(ogf::sim::CellClass::Free));

  std::vector<Column> cols;
  const auto ogf_est = classifyTruth(*truth, [&](const ogf::CellKey& k) {
    const auto q = ogf::filter::queryCell(map, k);
    return ev::CellEstimate{q.occupancyClass, q.predictiveProbability};
  });
  cols.push_back(makeColumn("OGF", *truth, ogf_est, ray_end, fmt::format("{}", map.allocatedCells())));
  std::vector<ev::CellEstimate> octo_est;
  if (octo) {
    octo_est = classifyTruth(*truth, [&](const ogf::CellKey& k) { return octo->estimate(k); });
    cols.push_back(makeColumn("OctoMap", *truth, octo_est, ray_end, fmt::format("{} leaves", octo->leafCount())));
  }
  if (const fs::path swept_path = fs::path(truth_dir) / "swept.grid"; fs::exists(swept_path)) {
    auto swept = ogf::sim::readGroundTruth(swept_path.string());
    if (!swept || swept->cells.size() != truth->cells.size()) {
      spdlog::warn("{}: {}; moving solids not scored", swept_path.string(),
                   swept ? "not the truth grid's size" : swept.error().message);
    } else {
      cols[0].swept = ev::scoreSwept(truth->cells, swept->cells, ogf_est);
      if (octo) cols[1].swept = ev::scoreSwept(truth->cells, swept->cells, octo_est);
    }
  }
  printTable(cols, gaps);
  if (split) {
    if (!config.fusion.extrinsic.quaternion && !ev::readSimExtrinsic(truth_dir)) {
      spdlog::error("--held-out: the run's sim.yaml has no extrinsic");
      return kExitFailed;
    }
    auto held = heldOutOnSimRun(truth_dir, config, clock, *split, !no_octomap);
    if (!held) {
      spdlog::error("--held-out: {}", held.error().message);
      return kExitFailed;
    }
    std::vector<std::string> names{"OGF"};
    if (!no_octomap) names.push_back("OctoMap");
    printHeldOut(*split, seed, names, *held);
  }

  int rc = kExitOk;
  if (!trajectories.empty() && !printTrajectoryErrors(truth_dir, trajectories)) rc = kExitFailed;
  const auto report = [&](const char* what, const ogf::Status& st) {
    if (!st) {
      spdlog::error("{}: {}", what, st.error().message);
      rc = kExitFailed;
    }
  };
  ev::HeightBand band;  // the same for the truth's pictures and the map's
  if (!png_dir.empty()) {
    std::error_code ec;
    fs::create_directories(png_dir, ec);
    const auto chosen = ogf::tools::pictureBand(ev::wallBand(*truth), png_zmin, png_zmax, "the truth");
    spdlog::info("{}: every picture shows cells with centres in z {:.2f} to {:.2f} m ({})", png_dir, chosen.z_min,
                 chosen.z_max, chosen.why);
    band = ev::HeightBand{chosen.z_min, chosen.z_max};
    report("--png", ev::writeTruthPng(*truth, band, scale, fs::path(png_dir) / "truth.png"));
    report("--png", ev::writeMapPngs(*truth, ogf_est, band, scale, png_dir, "ogf"));
    if (octo) report("--png", ev::writeMapPngs(*truth, octo_est, band, scale, png_dir, "octomap"));
  }
  if (!png_dir.empty() || !ply_out.empty()) {
    const auto cells = ogf::map_formats::collectCells(map);
    if (!ply_out.empty()) report("--export-ply", ogf::map_formats::writeOccupiedPly(cells, ply_out));
    if (!png_dir.empty()) {
      auto png = ogf::map_io::writeTopDownPngs(cells, {band.z_min, band.z_max}, png_dir);
      if (!png) report("--png", png.error());
    }
  }
  if (!octomap_out.empty()) {
    if (!octo) spdlog::warn("--write-octomap: no OctoMap was built");
    else report("--write-octomap", octo->write(octomap_out));
  }
  return rc;
}
