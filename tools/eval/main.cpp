// ogf-eval: scores an OGF map against the ground truth of a simulator run (ogf-sim's output folder), and
// an OctoMap built from the same run's rays beside it: accuracy (eq. 13 of Sun et al.), precision and
// recall of occupied, ROC AUC of the probabilities, coverage and gap filling. A table on stdout; top-down
// PNGs, the occupied cells as PLY and the OctoMap as .bt on request. With --odometry/--corrected, the
// absolute trajectory error of those poses against the run's trajectory_true.csv (with or without --map).
// This file owns the command line, the logs and the exit code; the work is in ogf_eval.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <ogf/filter/map_queries.hpp>
#include <ogf/sim/ground_truth.hpp>
#include <ogf/sim/pose_files.hpp>
#include <ogf/transport/logging.hpp>

#include "ogf/eval/map_loader.hpp"
#include "ogf/eval/map_scores.hpp"
#include "ogf/eval/octomap_baseline.hpp"
#include "ogf/eval/sim_measurements.hpp"
#include "ogf/eval/topdown_figures.hpp"
#include "ogf/eval/trajectory_error.hpp"
#include "ogf/map_io/cell_ply.hpp"
#include "ogf/map_io/map_cells.hpp"
#include "ogf/map_io/topdown_png.hpp"

namespace {

namespace fs = std::filesystem;
namespace ev = ogf::eval;

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;  // an input could not be read, or an output not written
constexpr int kExitUsage = 2;

struct Column {
  std::string name;
  ev::MapScores scores;
  std::int64_t occupied_cells = 0;  // classified occupied, inside the truth grid
  std::int64_t free_cells = 0;
  std::string map_cells;            // cells the map holds, as text
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
  Column c{std::move(name), ev::scoreMap(truth.cells, est, ray_end), 0, 0, std::move(map_cells)};
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
      "Exit 0 when scored, 1 when an input is unreadable or an output failed, 2 on bad flags."};
  std::string map_path, truth_dir, png_dir, octomap_in, octomap_out, ply_out, log_level = "info";
  std::string odometry_path, corrected_path;
  double max_range = 30.0, min_range = 0.4;
  bool no_octomap = false;
  ev::HeightBand band;
  int scale = 4;
  app.add_option("--map", map_path,
                 "OGF map: a map file (ogf-map --out) or a daemon snapshot (snapshot.ogfs); required unless "
                 "--odometry or --corrected is given")
      ->check(CLI::ExistingFile);
  app.add_option("--truth", truth_dir, "ogf-sim output folder (truth.grid, capture.pcap, odometry.csv, sim.yaml)")
      ->required()->check(CLI::ExistingDirectory);
  app.add_option("--png", png_dir, "Folder for truth.png, ogf_/octomap_classes.png, ogf_/octomap_errors.png and the "
                                   "map's occupancy.png/entropy.png");
  app.add_option("--png-zmin", band.z_min, "Bottom of the PNGs' height band, metres")->capture_default_str();
  app.add_option("--png-zmax", band.z_max, "Top of the PNGs' height band, metres")->capture_default_str();
  app.add_option("--png-scale", scale, "Pixels per cell in the truth/class/error PNGs")->capture_default_str()->check(CLI::Range(1, 32));
  auto* oin = app.add_option("--octomap", octomap_in, "Score this OctoMap (.bt) instead of building one")->check(CLI::ExistingFile);
  app.add_flag("--no-octomap", no_octomap, "Score the OGF only")->excludes(oin);
  app.add_option("--write-octomap", octomap_out, "Write the OctoMap built from the run as .bt");
  app.add_option("--export-ply", ply_out, "Write the OGF map's occupied cells as PLY");
  app.add_option("--max-range", max_range, "Ray cut for the recomputed measurements (use the mapper's), metres")->capture_default_str();
  app.add_option("--min-range", min_range, "Minimum range for the recomputed measurements, metres")->capture_default_str();
  app.add_option("--odometry", odometry_path, "Raw odometry poses to score (CSV, e.g. the run's odometry.csv)")
      ->check(CLI::ExistingFile);
  app.add_option("--corrected", corrected_path, "Corrected poses to score (CSV utime,x,y,z,qw,qx,qy,qz)")
      ->check(CLI::ExistingFile);
  app.add_option("--log-level", log_level, "trace|debug|info|warn|error")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int cli_rc = app.exit(e);  // prints the help or the error
    return cli_rc == 0 ? kExitOk : kExitUsage;
  }

  if (!ogf::transport::setupLoggingAt("ogf-eval", "--log-level", log_level)) return kExitUsage;

  std::vector<std::pair<std::string, std::string>> trajectories;
  if (!odometry_path.empty()) trajectories.emplace_back("odometry (raw)", odometry_path);
  if (!corrected_path.empty()) trajectories.emplace_back("corrected", corrected_path);
  if (map_path.empty()) {
    if (trajectories.empty()) {
      std::fprintf(stderr, "--map is required (unless --odometry or --corrected is given)\nRun with --help for more "
                           "information.\n");
      return kExitUsage;
    }
    return printTrajectoryErrors(truth_dir, trajectories) ? kExitOk : kExitFailed;
  }

  auto truth = ogf::sim::readGroundTruth((fs::path(truth_dir) / "truth.grid").string());
  if (!truth) {
    spdlog::error("--truth: {}", truth.error().message);
    return kExitFailed;
  }
  auto loaded = ev::loadOgfMap(map_path);
  if (!loaded) {
    spdlog::error("--map: {}", loaded.error().message);
    return kExitFailed;
  }
  const ogf::filter::BandedOgf& map = loaded->map;
  const double res = map.config().resolution;
  if (std::abs(res - truth->resolution) > 1e-9) {
    spdlog::error("the map's resolution {} m differs from the truth's {} m: cells would not line up", res, truth->resolution);
    return kExitFailed;
  }
  spdlog::info("{}: {} at seq {}, {} cells at {} m; truth {}x{}x{} ({} occupied, {} free)", map_path, loaded->kind,
               loaded->seq, map.allocatedCells(), res, truth->size[0], truth->size[1], truth->size[2],
               truth->count(ogf::sim::CellClass::Occupied), truth->count(ogf::sim::CellClass::Free));

  // The run's measurements, recomputed: where rays ended (gap filling) and the OctoMap's input.
  ogf::pipeline::MapperConfig config;
  config.filter = map.config();
  config.setResolution(res);
  config.fusion.measurement.max_range_m = max_range;
  config.fusion.measurement.min_range_m = min_range;
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
    });
    if (!counts) {
      spdlog::warn("recomputing the run's measurements: {}; gap filling not scored", counts.error().message);
      ray_end.clear();
      if (build) octo.reset();
    } else {
      gaps = true;
      if (build) octo->finish();
      spdlog::info("{}: {} scans, {} measured, {} measurements recomputed", truth_dir, counts->scans,
                   counts->scans_measured, counts->measurements);
    }
  }

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
  printTable(cols, gaps);

  int rc = kExitOk;
  if (!trajectories.empty() && !printTrajectoryErrors(truth_dir, trajectories)) rc = kExitFailed;
  const auto report = [&](const char* what, const ogf::Status& st) {
    if (!st) {
      spdlog::error("{}: {}", what, st.error().message);
      rc = kExitFailed;
    }
  };
  if (!png_dir.empty()) {
    std::error_code ec;
    fs::create_directories(png_dir, ec);
    report("--png", ev::writeTruthPng(*truth, band, scale, fs::path(png_dir) / "truth.png"));
    report("--png", ev::writeMapPngs(*truth, ogf_est, band, scale, png_dir, "ogf"));
    if (octo) report("--png", ev::writeMapPngs(*truth, octo_est, band, scale, png_dir, "octomap"));
  }
  if (!png_dir.empty() || !ply_out.empty()) {
    const auto cells = ogf::map_io::collectCells(map);
    if (!ply_out.empty()) report("--export-ply", ogf::map_io::writeOccupiedPly(cells, ply_out));
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
