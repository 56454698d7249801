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
#include <optional>
#include <string>
#include <vector>

#include <ogf/pipeline/scan_mapper.hpp>
#include <ogf/sim/ground_truth.hpp>
#include <ogf/sim/pose_files.hpp>
#include <ogf/transport/logging.hpp>

#include "ogf/common/command_line.hpp"
#include "ogf/eval/held_out.hpp"
#include "ogf/eval/map_estimate.hpp"
#include "ogf/eval/map_scores.hpp"
#include "ogf/eval/nav_scores.hpp"
#include "ogf/eval/octomap_baseline.hpp"
#include "ogf/eval/ray_ends.hpp"
#include "ogf/eval/score_tables.hpp"
#include "ogf/eval/sim_held_out.hpp"
#include "ogf/eval/sim_measurements.hpp"
#include "ogf/eval/static_capture.hpp"
#include "ogf/eval/topdown_figures.hpp"
#include "ogf/eval/trajectory_error.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_formats/nav_map_files.hpp"
#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/map_io/topdown_png.hpp"

namespace {

namespace fs = std::filesystem;
namespace ev = ogf::eval;

using ogf::cli::kExitOk;
constexpr int kExitFailed = 1;  // an input could not be read, or an output not written
using ogf::cli::kExitUsage;  // bad flags or configuration

// A step that cannot go on returns the exit code (after logging why); nullopt goes on.
using Stop = std::optional<int>;

const char* const kDescription =
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
    "Exit 0 when scored, 1 when an input is unreadable or an output failed, 2 on bad flags.";

struct Options {
  std::string map_path, truth_dir, png_dir, octomap_in, octomap_out, ply_out, log_level = "info";
  std::string odometry_path, corrected_path, config_path, pcap, calib, time_base;
  std::vector<std::string> alone_paths;  // maps of the same run's sources alone (--alone)
  double max_range = 30.0, min_range = 0.4, resolution = 0.2, held_out_share = 0.1;
  std::uint64_t seed = 1;
  bool held_out = false, is_static = false;
  bool no_octomap = false;
  bool nav = false;
  std::optional<double> png_zmin, png_zmax;  // default: the walls' band of the truth
  int scale = 1;
  // The options whose value replaces the configuration file's only when given.
  CLI::Option* time_opt = nullptr;
  CLI::Option* res_opt = nullptr;
  CLI::Option* max_opt = nullptr;
  CLI::Option* min_opt = nullptr;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--map", o.map_path,
                 "OGF map: a map file (ogf-map --out) or a daemon snapshot (snapshot.ogfs); required unless "
                 "--odometry or --corrected is given")
      ->check(CLI::ExistingFile);
  auto* truth_opt =
      app.add_option("--truth", o.truth_dir, "ogf-sim output folder (truth.grid, capture.pcap, odometry.csv, sim.yaml)")
          ->check(CLI::ExistingDirectory);
  auto* pcap_opt = app.add_option("--pcap", o.pcap, "A real capture of a sensor that did not move (with --static)")
                       ->check(CLI::ExistingFile)->excludes(truth_opt);
  app.add_flag("--static", o.is_static, "The --pcap sensor did not move: every ray from the sensor at the origin")
      ->needs(pcap_opt);
  app.add_option("--calib", o.calib, "Calibration for --pcap: VeloView XML or ROS YAML")->needs(pcap_opt)->check(CLI::ExistingFile);
  app.add_option("--config", o.config_path,
                 "ogf-mapper's configuration file (map, filter, fusion, time_base, pose_source) for the maps built "
                 "here: without --map, with --pcap, and for --held-out without --map; flags override it")
      ->check(CLI::ExistingFile);
  o.time_opt = app.add_option("--time", o.time_base,
                                  "Clock the run's odometry is on: auto, device or host (see ogf-map --time); "
                                  "default: the config's time_base, else auto")
                       ->check(CLI::IsMember({"auto", "device", "host"}));
  o.res_opt = app.add_option("--resolution", o.resolution, "Cell size of the maps built here (without --map), metres")
                      ->capture_default_str();
  app.add_flag("--held-out", o.held_out, "Also score both maps on rays held out of them (see above)");
  app.add_option("--held-out-share", o.held_out_share, "Share of every scan's rays held out")
      ->capture_default_str()->check(ogf::cli::between(0.01, 0.5));
  app.add_option("--seed", o.seed, "Seed of the held-out split")->capture_default_str();
  app.add_option("--png", o.png_dir, "Folder for truth.png, ogf_/octomap_classes.png, ogf_/octomap_errors.png and the "
                                   "map's occupancy.png/entropy.png");
  app.add_option("--png-zmin", o.png_zmin, "Bottom of the PNGs' height band, metres (default: the truth's walls' band)");
  app.add_option("--png-zmax", o.png_zmax, "Top of the PNGs' height band, metres (default: the truth's walls' band)");
  app.add_option("--png-scale", o.scale, "Least pixels per cell in the truth/class/error PNGs (they are at least 800 px wide or high)")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 32));
  auto* oin = app.add_option("--octomap", o.octomap_in, "Score this OctoMap (.bt) instead of building one")->check(CLI::ExistingFile);
  app.add_flag("--no-octomap", o.no_octomap, "Score the OGF only")->excludes(oin);
  app.add_option("--write-octomap", o.octomap_out, "Write the OctoMap built from the run as .bt");
  app.add_option("--export-ply", o.ply_out, "Write the OGF map's occupied cells as PLY");
  o.max_opt = app.add_option("--max-range", o.max_range, "Ray cut for the recomputed measurements (use the mapper's), metres")->capture_default_str();
  o.min_opt = app.add_option("--min-range", o.min_range, "Minimum range for the recomputed measurements, metres")->capture_default_str();
  app.add_option("--alone", o.alone_paths,
                 "A map of the same world made by some of the sources alone (a lidar of a rig, one robot), "
                 "repeatable: each is scored beside --map, with the coverage of their union")
      ->check(CLI::ExistingFile)->needs(truth_opt);
  app.add_option("--odometry", o.odometry_path, "Raw odometry poses to score (CSV, e.g. the run's odometry.csv)")
      ->check(CLI::ExistingFile);
  app.add_option("--corrected", o.corrected_path, "Corrected poses to score (CSV utime,x,y,z,qw,qx,qy,qz)")
      ->check(CLI::ExistingFile);
  app.add_flag("--nav", o.nav,
               "Also score the map's 2-D navigation grid (the band of the --config file's nav.* keys) against the "
               "truth's columns");
  app.add_option("--log-level", o.log_level, "trace|debug|info|warn|error")->capture_default_str();
}

// The settings of the maps built here: --config's, with the flags over them.
struct Settings {
  ogf::pipeline::MapperConfig built;
  ogf::map_io::TimeBase clock = ogf::map_io::TimeBase::kAuto;
  bool is_static = false;
  std::optional<ev::HeldOutSplit> split;
  ogf::navigation::NavBand nav_band;
};

Stop resolveSettings(const Options& o, Settings& s) {
  ogf::mapper_daemon::MapperOptions file;  // the defaults when there is no --config
  if (!o.config_path.empty()) {
    auto read = ogf::map_io::readOfflineConfig(o.config_path, ogf::mapper_daemon::kUsedByEval);
    if (!read) {
      spdlog::error("--config: {}", read.error().message);
      return ogf::cli::exitCodeFor(read.error());
    }
    if (const auto note = read->unusedNote("ogf-eval"); !note.empty()) spdlog::info("--config: {}", note);
    file = read->options;
  }
  s.built = file.map;
  s.nav_band = file.nav.band;
  s.clock = o.time_opt->count() == 0 ? file.time_base
            : o.time_base == "host"  ? ogf::map_io::TimeBase::kHost
            : o.time_base == "device" ? ogf::map_io::TimeBase::kDevice
                                      : ogf::map_io::TimeBase::kAuto;
  s.is_static = o.is_static || file.pose_source == ogf::mapper_daemon::PoseSource::kStatic;
  if (o.config_path.empty() || o.res_opt->count() > 0) s.built.setResolution(o.resolution);
  if (o.config_path.empty() || o.max_opt->count() > 0) s.built.fusion.measurement.max_range_m = o.max_range;
  if (o.config_path.empty() || o.min_opt->count() > 0) s.built.fusion.measurement.min_range_m = o.min_range;
  if (auto st = s.built.validate(); !st) {
    spdlog::error("configuration: {}", st.error().message);
    return ogf::cli::exitCodeFor(st.error());
  }
  if (o.held_out) s.split.emplace(o.held_out_share, o.seed);
  return std::nullopt;
}

// Says once that odometry and scans are on different clocks when no scan could be placed.
void reportClocks(const ev::SimMeasurementCounts& counts) {
  if (counts.scans_measured == 0 && !counts.clock_mismatch.empty()) spdlog::warn("clocks: {}", counts.clock_mismatch);
}

// A real capture of a sensor that did not move: both maps built from its returns, scored on how they hold
// those returns; with a split, also built from the kept rays and scored on the held-out ones.
int evaluateStaticCapture(const Options& o, const Settings& s) {
  auto capture = ev::readStaticCapture(o.pcap, o.calib, s.built);
  if (!capture) {
    spdlog::error("--pcap: {}", capture.error().message);
    return kExitFailed;
  }
  if (!capture->counts.warning.empty()) spdlog::warn("--pcap: {}", capture->counts.warning);
  spdlog::info("calibration: {}", capture->counts.calibration);
  const auto& m = s.built.fusion.measurement;
  spdlog::info("{}: {} scans, {} points; resolution {} m, range {}-{} m", o.pcap, capture->scans.size(),
               capture->counts.points, m.resolution_m, m.min_range_m, m.max_range_m);

  auto full = ev::buildStaticMaps(*capture, s.built, [](std::int64_t, std::size_t) { return true; });
  if (!full) {
    spdlog::error("{}", full.error().message);
    return kExitFailed;
  }
  const ev::ReturnRange range = ev::scoredReturnRange(m);
  const auto returns = ev::scoreOwnReturns(*capture, *full, m.resolution_m, range);
  std::fputs(ev::returnsTable(range.from_m, range.to_m, returns,
                              {fmt::format("{}", full->ogf.filter().allocatedCells()),
                               fmt::format("{} leaves", full->octo.leafCount())})
                 .c_str(),
             stdout);
  if (!o.octomap_out.empty()) {
    if (const auto st = full->octo.write(o.octomap_out); !st) {
      spdlog::error("--write-octomap: {}", st.error().message);
      return kExitFailed;
    }
  }
  if (s.split) {
    const auto& split = *s.split;
    auto kept = ev::buildStaticMaps(*capture, s.built, [&](std::int64_t scan, std::size_t i) { return !split.heldOut(scan, i); });
    if (!kept) {
      spdlog::error("{}", kept.error().message);
      return kExitFailed;
    }
    std::fputs(ev::heldOutTable(split, o.seed, {"OGF", "OctoMap"}, ev::scoreHeldOutReturns(*capture, *kept, split, m)).c_str(),
               stdout);
  }
  return kExitOk;
}

using Trajectories = std::vector<std::pair<std::string, std::string>>;  // label, CSV file

Trajectories trajectoriesOf(const Options& o) {
  Trajectories trajectories;
  if (!o.odometry_path.empty()) trajectories.emplace_back("odometry (raw)", o.odometry_path);
  if (!o.corrected_path.empty()) trajectories.emplace_back("corrected", o.corrected_path);
  return trajectories;
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

// The map scored: --map, or one built here from the run's rays (in the replay of the run).
struct ScoredMap {
  std::optional<ogf::map_formats::LoadedMap> loaded;
  std::optional<ogf::pipeline::ScanMapper> own;
  ogf::pipeline::MapperConfig config;
  const ogf::filter::BandedOgf& map() const { return own ? own->filter() : loaded->map; }
};

Stop openScoredMap(const Options& o, const Settings& s, const ogf::sim::GroundTruth& truth, ScoredMap& scored) {
  scored.config = s.built;
  if (!o.map_path.empty()) {
    auto l = ogf::map_formats::loadOgfMap(o.map_path);
    if (!l) {
      spdlog::error("--map: {}", l.error().message);
      return kExitFailed;
    }
    scored.loaded.emplace(std::move(*l));
    scored.config.filter = scored.loaded->map.config();
    scored.config.setResolution(scored.loaded->map.config().resolution);
  } else {
    auto m = ogf::pipeline::ScanMapper::create(scored.config);
    if (!m) {
      spdlog::error("configuration: {}", m.error().message);
      return ogf::cli::exitCodeFor(m.error());
    }
    scored.own.emplace(std::move(*m));
  }
  const double res = scored.config.filter.resolution;
  if (std::abs(res - truth.resolution) > 1e-9) {
    spdlog::error("the map's resolution {} m differs from the truth's {} m: cells would not line up", res, truth.resolution);
    return kExitFailed;
  }
  return std::nullopt;
}

// The run's measurements, recomputed: where rays ended (gap filling), the OctoMap's input, and the OGF's
// when it is built here.
struct RunMeasurements {
  std::vector<std::uint8_t> ray_end;
  std::optional<ev::OctomapBaseline> octo;
  bool gaps = false;
};

Stop openOctomap(const Options& o, double resolution, RunMeasurements& run) {
  if (!o.no_octomap && !o.octomap_in.empty()) {
    auto bt = ev::OctomapBaseline::load(o.octomap_in);
    if (!bt) {
      spdlog::error("--octomap: {}", bt.error().message);
      return kExitFailed;
    }
    run.octo.emplace(std::move(*bt));
  } else if (!o.no_octomap) {
    run.octo.emplace(resolution);
  }
  return std::nullopt;
}

Stop recomputeMeasurements(const Options& o, const Settings& s, const ogf::sim::GroundTruth& truth, ScoredMap& scored,
                           RunMeasurements& run) {
  auto extr = ev::readSimExtrinsic(o.truth_dir);
  if (!extr) {
    if (scored.own) {
      spdlog::error("{}: the map cannot be built from the run without it", extr.error().message);
      return kExitFailed;
    }
    spdlog::warn("{}; gap filling not scored{}", extr.error().message, run.octo && o.octomap_in.empty() ? ", no OctoMap" : "");
    if (o.octomap_in.empty()) run.octo.reset();
    return std::nullopt;
  }
  scored.config.fusion.extrinsic = *extr;
  run.ray_end.assign(truth.cells.size(), 0);
  const bool build = run.octo && o.octomap_in.empty();
  auto counts = ev::replaySimMeasurements(o.truth_dir, scored.config, [&](std::span<const ogf::Measurement> ms) {
    ev::markRayEnds(truth, ms, run.ray_end);
    if (build) run.octo->insert(ms);
    if (scored.own) scored.own->apply(ms);
  }, s.clock);
  if (!counts && scored.own) {
    spdlog::error("building the map from the run: {}", counts.error().message);
    return kExitFailed;
  }
  if (!counts) {
    spdlog::warn("recomputing the run's measurements: {}; gap filling not scored", counts.error().message);
    run.ray_end.clear();
    if (build) run.octo.reset();
    return std::nullopt;
  }
  run.gaps = true;
  if (build) run.octo->finish();
  reportClocks(*counts);
  spdlog::info("{}: {} scans, {} measured, {} measurements recomputed", o.truth_dir, counts->scans,
               counts->scans_measured, counts->measurements);
  return std::nullopt;
}

void logScoredMap(const Options& o, const ScoredMap& scored, const ogf::sim::GroundTruth& truth) {
  const auto& map = scored.map();
  spdlog::info("{}: {}, {} cells at {} m; truth {}x{}x{} ({} occupied, {} free)",
               scored.own ? o.truth_dir : o.map_path,
               scored.own ? std::string("built from the run")
                          : fmt::format("{} at seq {}", scored.loaded->kind, scored.loaded->seq),
               map.allocatedCells(), scored.config.filter.resolution, truth.size[0], truth.size[1], truth.size[2],
               truth.count(ogf::sim::CellClass::Occupied), truth.count(ogf::sim::CellClass::Free));
}

// Each map's class and probability for every truth cell.
struct TruthEstimates {
  std::vector<ev::CellEstimate> ogf;
  std::vector<ev::CellEstimate> octo;  // empty without an OctoMap
};

TruthEstimates estimateTruth(const ogf::sim::GroundTruth& truth, const ScoredMap& scored, const RunMeasurements& run) {
  TruthEstimates est;
  const auto& map = scored.map();
  est.ogf = ev::classifyTruth(truth, [&](const ogf::CellKey& k) { return ev::ogfEstimate(map, k); });
  if (run.octo) est.octo = ev::classifyTruth(truth, [&](const ogf::CellKey& k) { return run.octo->estimate(k); });
  return est;
}

// One column per map; the moving solids' rows when the run has swept.grid.
std::vector<ev::MapColumn> scoreColumns(const Options& o, const ogf::sim::GroundTruth& truth, const ScoredMap& scored,
                                        const RunMeasurements& run, const TruthEstimates& est) {
  std::vector<ev::MapColumn> cols;
  cols.push_back(ev::makeColumn("OGF", truth, est.ogf, run.ray_end, fmt::format("{}", scored.map().allocatedCells())));
  if (run.octo) cols.push_back(ev::makeColumn("OctoMap", truth, est.octo, run.ray_end, fmt::format("{} leaves", run.octo->leafCount())));
  if (const fs::path swept_path = fs::path(o.truth_dir) / "swept.grid"; fs::exists(swept_path)) {
    auto swept = ogf::sim::readGroundTruth(swept_path.string());
    if (!swept || swept->cells.size() != truth.cells.size()) {
      spdlog::warn("{}: {}; moving solids not scored", swept_path.string(),
                   swept ? "not the truth grid's size" : swept.error().message);
    } else {
      cols[0].swept = ev::scoreSwept(truth.cells, swept->cells, est.ogf);
      if (run.octo) cols[1].swept = ev::scoreSwept(truth.cells, swept->cells, est.octo);
    }
  }
  return cols;
}

Stop scoreHeldOut(const Options& o, const Settings& s, const ScoredMap& scored) {
  if (!s.split) return std::nullopt;
  if (!scored.config.fusion.extrinsic.quaternion && !ev::readSimExtrinsic(o.truth_dir)) {
    spdlog::error("--held-out: the run's sim.yaml has no extrinsic");
    return kExitFailed;
  }
  auto held = ev::heldOutOnSimRun(o.truth_dir, scored.config, s.clock, *s.split, !o.no_octomap);
  if (!held) {
    spdlog::error("--held-out: {}", held.error().message);
    return kExitFailed;
  }
  reportClocks(held->counts);
  std::vector<std::string> names{"OGF"};
  if (!o.no_octomap) names.push_back("OctoMap");
  std::fputs(ev::heldOutTable(*s.split, o.seed, names, held->scores).c_str(), stdout);
  return std::nullopt;
}

// The PNGs, the PLY and the OctoMap asked for; false when one could not be written (each is tried).
bool writeOutputs(const Options& o, const ogf::sim::GroundTruth& truth, const ScoredMap& scored,
                  const RunMeasurements& run, const TruthEstimates& est) {
  bool ok = true;
  const auto report = [&](const char* what, const ogf::Status& st) {
    if (!st) {
      spdlog::error("{}: {}", what, st.error().message);
      ok = false;
    }
  };
  ev::HeightBand band;  // the same for the truth's pictures and the map's
  if (!o.png_dir.empty()) {
    std::error_code ec;
    fs::create_directories(o.png_dir, ec);
    const auto chosen = ogf::tools::pictureBand(ev::wallBand(truth), o.png_zmin, o.png_zmax, "the truth");
    spdlog::info("{}: every picture shows cells with centres in z {:.2f} to {:.2f} m ({})", o.png_dir, chosen.z_min,
                 chosen.z_max, chosen.why);
    band = ev::HeightBand{chosen.z_min, chosen.z_max};
    report("--png", ev::writeTruthPng(truth, band, o.scale, fs::path(o.png_dir) / "truth.png"));
    report("--png", ev::writeMapPngs(truth, est.ogf, band, o.scale, o.png_dir, "ogf"));
    if (run.octo) report("--png", ev::writeMapPngs(truth, est.octo, band, o.scale, o.png_dir, "octomap"));
  }
  if (!o.png_dir.empty() || !o.ply_out.empty()) {
    const auto cells = ogf::map_formats::collectCells(scored.map());
    if (!o.ply_out.empty()) report("--export-ply", ogf::map_formats::writeOccupiedPly(cells, o.ply_out));
    if (!o.png_dir.empty()) {
      // Over the truth's grid, as truth.png and the class and error pictures are.
      const ogf::map_io::TopDownArea area{truth.min_key.x, truth.min_key.y, truth.min_key.x + truth.size[0] - 1,
                                          truth.min_key.y + truth.size[1] - 1};
      auto png = ogf::map_io::writeTopDownPngs(cells, {band.z_min, band.z_max}, o.png_dir, area);
      if (!png) report("--png", png.error());
    }
  }
  if (!o.octomap_out.empty()) {
    if (!run.octo) spdlog::warn("--write-octomap: no OctoMap was built");
    else report("--write-octomap", run.octo->write(o.octomap_out));
  }
  return ok;
}

// A simulator run: the map and OctoMap scored against its truth, then the held-out test, the
// trajectories and the outputs asked for.
// The maps of the sources alone (--alone): a column each beside the map's, and the lines that compare the
// map with them: the coverage of their union, and the better one's accuracy.
struct AloneMaps {
  std::vector<ev::MapColumn> columns;
  std::vector<std::vector<ev::CellEstimate>> estimates;
};

Stop scoreAlone(const Options& o, const ogf::sim::GroundTruth& truth, const RunMeasurements& run, AloneMaps& alone) {
  for (const auto& path : o.alone_paths) {
    auto l = ogf::map_formats::loadOgfMap(path);
    if (!l) {
      spdlog::error("--alone: {}", l.error().message);
      return kExitFailed;
    }
    if (std::abs(l->map.config().resolution - truth.resolution) > 1e-9) {
      spdlog::error("--alone {}: resolution {} m differs from the truth's {} m", path, l->map.config().resolution,
                    truth.resolution);
      return kExitFailed;
    }
    const auto& map = l->map;
    alone.estimates.push_back(ev::classifyTruth(truth, [&](const ogf::CellKey& k) { return ev::ogfEstimate(map, k); }));
    alone.columns.push_back(ev::makeColumn(fs::path(path).stem().string(), truth, alone.estimates.back(), run.ray_end,
                                           fmt::format("{}", map.allocatedCells())));
  }
  return std::nullopt;
}

void printAloneComparison(const ogf::sim::GroundTruth& truth, const ev::MapColumn& combined, const AloneMaps& alone) {
  if (alone.columns.empty()) return;
  double better = 0;
  for (const auto& c : alone.columns) better = std::max(better, c.scores.accuracy);
  std::printf("\nthe map against its sources alone\n");
  const ev::UnionCoverage u = ev::unionCoverage(truth.cells, alone.estimates);
  std::printf("  coverage: %.4f, the union of the sources alone %.4f (cells one classifies and none contradicts; "
              "%.4f with the contradicted ones)\n",
              combined.scores.coverage, u.consistent, u.any);
  std::printf("  accuracy: %.4f, the better source alone %.4f\n", combined.scores.accuracy, better);
}

int scoreSimRun(const Options& o, const Settings& s, const Trajectories& trajectories) {
  auto truth = ogf::sim::readGroundTruth((fs::path(o.truth_dir) / "truth.grid").string());
  if (!truth) {
    spdlog::error("--truth: {}", truth.error().message);
    return kExitFailed;
  }
  ScoredMap scored;
  if (auto stop = openScoredMap(o, s, *truth, scored)) return *stop;
  RunMeasurements run;
  if (auto stop = openOctomap(o, scored.config.filter.resolution, run)) return *stop;
  if (auto stop = recomputeMeasurements(o, s, *truth, scored, run)) return *stop;
  logScoredMap(o, scored, *truth);

  const TruthEstimates est = estimateTruth(*truth, scored, run);
  AloneMaps alone;
  if (auto stop = scoreAlone(o, *truth, run, alone)) return *stop;
  auto columns = scoreColumns(o, *truth, scored, run, est);
  const ev::MapColumn combined = columns.front();
  columns.insert(columns.begin() + 1, alone.columns.begin(), alone.columns.end());
  std::fputs(ev::scoreTable(columns, run.gaps).c_str(), stdout);
  printAloneComparison(*truth, combined, alone);
  if (o.nav) {
    auto grid = ogf::map_formats::projectCells(ogf::map_formats::collectCells(scored.map()), s.nav_band);
    if (!grid) {
      spdlog::error("--nav: {}", grid.error().message);
      return kExitUsage;
    }
    std::fputs(ev::navScoreTable(ev::scoreNavGrid(*truth, *grid), *grid).c_str(), stdout);
  }
  if (auto stop = scoreHeldOut(o, s, scored)) return *stop;

  int rc = kExitOk;
  if (!trajectories.empty() && !printTrajectoryErrors(o.truth_dir, trajectories)) rc = kExitFailed;
  if (!writeOutputs(o, *truth, scored, run, est)) rc = kExitFailed;
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!ogf::transport::setupLoggingAt("ogf-eval", "--log-level", o.log_level)) return kExitUsage;

  Settings settings;
  if (auto stop = resolveSettings(o, settings)) return *stop;
  if (!o.pcap.empty()) {
    if (!settings.is_static) {
      std::fprintf(stderr, "--pcap needs --static (a capture with odometry is scored through an ogf-sim run)\n");
      return kExitUsage;
    }
    return evaluateStaticCapture(o, settings);
  }
  if (o.truth_dir.empty()) {
    std::fprintf(stderr, "--truth DIR (an ogf-sim run) or --pcap FILE --static is required\nRun with --help for more "
                         "information.\n");
    return kExitUsage;
  }
  const Trajectories trajectories = trajectoriesOf(o);
  if (o.map_path.empty() && !trajectories.empty())
    return printTrajectoryErrors(o.truth_dir, trajectories) ? kExitOk : kExitFailed;
  return scoreSimRun(o, settings, trajectories);
}
