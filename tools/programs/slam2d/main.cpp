// ogf-slam2d: grid-based FastSLAM (or scan matching alone) over a CARMEN log of the Freiburg 2-D SLAM
// benchmark. Writes the benchmark's result log (every laser record with its corrected robot pose in both
// pose triples and its original ipc_timestamp), the final map as PNG, and a summary line; with
// --relations it also scores the run (Kümmerle et al. 2009). This file owns the command line, the files,
// the progress bar and the exit code; the work is in ogf::slam and ogf_slam2d (tools/lib/slam2d).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <ogf/slam/pose_corrector.hpp>
#include <ogf/slam_io/relations.hpp>
#include <ogf/tools/png_writer.hpp>
#include <optional>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/slam2d/map_image.hpp"
#include "ogf/slam2d/run_outputs.hpp"
#include "ogf/slam2d/slam2d_config.hpp"
#include "ogf/slam2d/slam_log.hpp"
#include "ogf/slam2d/slam_run.hpp"

namespace {

namespace slam = ogf::slam;
namespace s2 = ogf::slam2d;

using ogf::cli::kExitOk;
constexpr int kExitFailed = 1;  // an input could not be read or an output not written
using ogf::cli::kExitUsage;     // bad flags or configuration

// A one-line bar on stderr, drawn only when stderr is a terminal, at most every 100 ms.
class ProgressBar {
 public:
  ProgressBar() : enabled_(isatty(STDERR_FILENO) == 1) {}
  void update(std::size_t done, std::size_t total) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (done != total && drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    drawn_ = true;
    constexpr std::size_t kWidth = 40;
    const std::size_t filled = total == 0 ? kWidth : done * kWidth / total;
    std::fprintf(stderr, "\r[%s%s] %zu/%zu scans", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, ' ').c_str(), done, total);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point last_{};
};

void fail(const std::string& message) { std::fprintf(stderr, "ogf-slam2d: %s\n", message.c_str()); }

struct Options {
  std::string log_path, out_path, png_path, relations_path, mode_text = "rbpf", odometry_text = "laser";
  slam::PoseCorrectorConfig config;
  std::size_t max_records = 0;
  bool no_two_step = false;

  Options() {
    // The benchmark's published RBPF has 50 particles (Kümmerle et al. 2009); with 50, ACES scores 0.061 m
    // over seeds 42/1/7 against 0.080 with gmapping's 30, fr079 0.053 against 0.056, Intel 0.041 against
    // 0.040 (docs/slam.md, "The benchmark"). The library keeps gmapping's 30 for the mapper's correction.
    config.slam.particles = 50;
  }
};

const char* const kDescription =
    "Grid-based FastSLAM (Grisetti et al. 2007: RBPF with the improved proposal, two-step sampling, "
    "selective "
    "resampling) over a CARMEN log (FLASER, ROBOTLASER1, ODOM). A scan is processed once the robot moved "
    "--linear-update or --angular-update; every laser record gets a pose (the best particle's last pose "
    "plus "
    "the odometry since). Writes a CARMEN result log with the corrected pose in both triples and the "
    "original "
    "ipc_timestamp, the final map as PNG, a summary line.\n"
    "Exit 0 on success, 1 when an input is unreadable or an output failed, 2 on bad flags.";

// The files, the mode and when a scan is processed.
void addRunOptions(CLI::App& app, Options& o) {
  app.add_option("--log", o.log_path, "CARMEN log (.clf)")->required()->check(CLI::ExistingFile);
  app.add_option("--particles", o.config.slam.particles, "Particles (rbpf mode)")->capture_default_str();
  app.add_option("--out", o.out_path, "Result log: every laser record with the corrected pose");
  app.add_option("--map-png", o.png_path, "The best particle's final map as PNG, trajectory in red");
  app.add_option("--mode", o.mode_text, "none | scan-match | rbpf")->capture_default_str();
  app.add_option("--seed", o.config.slam.seed, "Random seed (runs are deterministic per seed)")
      ->capture_default_str();
  app.add_option("--max-records", o.max_records, "Stop after this many laser records (0: all)")
      ->capture_default_str();
  app.add_option("--linear-update", o.config.slam.linear_update_m,
                 "Process a scan after this translation, m (scan-match mode: 0.2)")
      ->capture_default_str();
  app.add_option("--angular-update", o.config.slam.angular_update_rad,
                 "... or this rotation, rad (scan-match mode: 0.05)")
      ->capture_default_str();
  app.add_option("--resolution", o.config.slam.grid_resolution_m, "Grid cell edge, m")->capture_default_str();
  app.add_option("--usable-range", o.config.slam.map_update.usable_range_m,
                 "Beams are matched and mapped up to this range, m (longer ones mark free space only)")
      ->capture_default_str();
}

// The filter's and the matcher's tuning, the odometry source and the relations to score against.
void addTuningOptions(CLI::App& app, Options& o) {
  app.add_flag("--no-two-step", o.no_two_step,
               "Start each particle's scan match from the odometry prediction, not from a "
               "motion-model draw (two-step sampling off)");
  app.add_option("--observation-gain", o.config.slam.observation_gain,
                 "Weights tempered as exp(l / (gain * particles)) (gmapping's obsSigmaGain)")
      ->capture_default_str();
  app.add_option("--proposal-step", o.config.slam.proposal.sample_step_m,
                 "Spacing of the improved proposal's sample grid, m")
      ->capture_default_str();
  app.add_option("--proposal-step-angle", o.config.slam.proposal.sample_step_rad, "... and in heading, rad")
      ->capture_default_str();
  // Options that show their default in --help.
  const auto tuning = [&app](const char* name, auto& value, const char* help) {
    app.add_option(name, value, help)->capture_default_str();
  };
  tuning("--likelihood-sigma", o.config.slam.matcher.likelihood_sigma_m,
         "Sigma of the matcher's endpoint Gaussian, m (gmapping's lsigma)");
  tuning("--unmatched-distance", o.config.slam.matcher.unmatched_distance_m,
         "A beam with no occupied cell near its endpoint counts as this far off, m (scan-match mode: 0.3)");
  tuning("--weight-unmatched-distance", o.config.slam.weight_unmatched_distance_m,
         "The same in the particle weights only, m (0: --unmatched-distance)");
  tuning("--search-window", o.config.slam.matcher.search_window_cells,
         "Endpoint searched within +-n cells (gmapping's kernelSize)");
  tuning("--heading-starts", o.config.slam.matcher.heading_starts,
         "Extra scan-match climbs from the start heading +-k*--heading-start-step, k = 1..n (scan-match "
         "mode: 2)");
  tuning("--heading-start-step", o.config.slam.matcher.heading_start_step_rad,
         "Heading offset between those starts, rad");
  app.add_option("--no-return-free-range", o.config.slam.map_update.no_return_free_range_m,
                 "\"No return\" readings mark free space up to this range, m (0: skipped, as gmapping does)")
      ->capture_default_str();
  app.add_option(
         "--odometry", o.odometry_text,
         "laser: each laser record's own robot pose (FLASER's odom triple), the pose the logger paired with "
         "the scan; odom: ODOM lines interpolated to each laser stamp (the laser records' poses when the log "
         "has none). intel's laser stamps step back 631 times, so interpolation there pairs scans with the "
         "wrong odometry (scan matching, first 3000 records: 0.79 m vs 0.039 m)")
      ->check(CLI::IsMember({"odom", "laser"}))
      ->capture_default_str();
  app.add_option("--relations", o.relations_path, "Score the run against these ground-truth relations")
      ->check(CLI::ExistingFile);
}

// Each step returns nullopt to go on, or the exit code ogf-slam2d stops with (its reason printed).
using Stop = std::optional<int>;

// The corrector's configuration from the flags given.
Stop configure(const CLI::App& app, Options& o) {
  const auto given = [&app](const char* flag) { return app.count(flag) > 0; };
  const s2::PresetFlagsGiven preset{given("--linear-update"), given("--angular-update"),
                                    given("--unmatched-distance"), given("--heading-starts"),
                                    given("--heading-start-step")};
  auto config = s2::slam2dConfig(o.config, o.mode_text, preset, !o.no_two_step);
  if (!config) {
    fail(config.error().message);
    return kExitUsage;
  }
  o.config = *config;
  return std::nullopt;
}

// The CARMEN log, its malformed lines said; stops when it cannot be read or holds no laser record.
Stop readLog(const Options& o, s2::SlamLog& log) {
  std::ifstream in(o.log_path);
  if (!in) {
    fail("--log: cannot open " + o.log_path);
    return kExitFailed;
  }
  log = s2::readSlamLog(in, o.log_path, o.max_records);
  for (const auto& e : log.malformed) fail("skipped: " + e.message);
  if (log.lasers.empty()) {
    fail("--log: " + o.log_path + " holds no FLASER or ROBOTLASER1 record");
    return kExitFailed;
  }
  return std::nullopt;
}

// The run with its wall and CPU time.
struct TimedRun {
  std::optional<s2::SlamRunResult> result;
  double seconds = 0.0, cpu_seconds = 0.0;
};

Stop runTimed(const Options& o, const s2::SlamLog& log, TimedRun& timed) {
  ProgressBar bar;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  const auto source =
      o.odometry_text == "laser" ? s2::OdometrySource::kLaserRecords : s2::OdometrySource::kOdomLines;
  auto run = s2::runSlam(log, source, o.config,
                         [&](std::size_t done, std::size_t total) { bar.update(done, total); });
  timed.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  timed.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  if (!run) {
    fail(run.error().message);
    return kExitUsage;
  }
  timed.result.emplace(std::move(*run));
  return std::nullopt;
}

// The result log and the map picture; the exit code (1 when one could not be written).
int writeOutputs(const Options& o, const s2::SlamLog& log, const s2::SlamRunResult& run) {
  int rc = kExitOk;
  if (run.reversed_steps_repaired > 0) {
    fail("odometry moved forward in " + std::to_string(run.reversed_steps_repaired) +
         " steps while ODOM's tv was negative; their translation was reversed");
  }
  if (!o.out_path.empty()) {
    if (auto st = s2::writeResultLog(o.out_path, log, run.corrected); !st) {
      fail("--out: " + st.error().message);
      rc = kExitFailed;
    }
  }
  if (!o.png_path.empty() && run.map) {
    std::string error;
    if (!ogf::tools::writePng(o.png_path, s2::renderMap(*run.map, run.corrected), error)) {
      fail("--map-png: " + error);
      rc = kExitFailed;
    }
  }
  return rc;
}

void printSummary(const Options& o, const s2::SlamLog& log, const TimedRun& timed) {
  const double span = log.lasers.back().stamp.ipc_timestamp - log.lasers.front().stamp.ipc_timestamp;
  const auto& st = timed.result->statistics;
  std::printf(
      "ogf-slam2d: %s: %zu laser records, %zu processed, mode %s, %zu particles, %zu resamplings, "
      "%zu untrusted matches, %.1f s wall, %.1f s CPU (%.1fx real time by CPU)\n",
      o.log_path.c_str(), log.lasers.size(), st.scans_processed, o.mode_text.c_str(),
      o.config.mode == slam::CorrectionMode::kRbpf ? o.config.slam.particles : std::size_t{1}, st.resamplings,
      st.untrusted_matches, timed.seconds, timed.cpu_seconds,
      timed.cpu_seconds > 0.0 ? span / timed.cpu_seconds : 0.0);
}

// --relations: the run scored against the ground-truth relations.
Stop scoreRun(const Options& o, const s2::SlamLog& log, const s2::SlamRunResult& run) {
  if (o.relations_path.empty()) return std::nullopt;
  std::ifstream rin(o.relations_path);
  auto relations = ogf::slam_io::readRelations(rin, o.relations_path);
  if (!relations) {
    fail("--relations: " + relations.error().message);
    return kExitFailed;
  }
  const auto m = ogf::slam_io::evaluateRelations(s2::stampedTrajectory(log, run.corrected), *relations);
  std::printf("trans %.4f ± %.4f m max %.3f, rot %.3f ± %.3f deg, %zu relations (%zu without poses)\n",
              m.translation.mean, m.translation.std, m.translation.max, m.rotation_deg.mean,
              m.rotation_deg.std, m.translation.count, m.unmatched);
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{kDescription};
  addRunOptions(app, o);
  addTuningOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (const Stop stop = configure(app, o)) return *stop;
  s2::SlamLog log;
  if (const Stop stop = readLog(o, log)) return *stop;
  TimedRun timed;
  if (const Stop stop = runTimed(o, log, timed)) return *stop;
  const int rc = writeOutputs(o, log, *timed.result);
  printSummary(o, log, timed);
  if (const Stop stop = scoreRun(o, log, *timed.result)) return *stop;
  return rc;
}
