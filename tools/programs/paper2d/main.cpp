// ogf-paper2d: reproduces Sec. VI-A of Sun et al. (ACC 2018). On a 25 × 25 ground truth (built in, or
// --truth FILE.pgm) it draws samples without repetition (or reads --samples FILE.csv), runs occupancy grid
// mapping, EP and the OGF with σ = 1 grid unit and r_o/r_f = 0.65/0.35, and prints the table of d(OGF, EP)
// (eq. 12) and accuracies (eq. 13) against the number of samples, then whether the paper's claims hold.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/paper2d/experiment.hpp"
#include "ogf/paper2d/figures.hpp"
#include "ogf/paper2d/ground_truth.hpp"
#include "ogf/transport/logging.hpp"

namespace {

constexpr int kClaimsFailed = ogf::cli::kExitFailure;

bool writeMeans(const std::string& path, const ogf::paper2d::GroundTruth& truth,
                const ogf::paper2d::ExperimentRun& run) {
  std::ofstream out(path, std::ios::trunc);
  out << "row,col,m_ogf,m_ep\n";
  char line[128];
  for (int r = 0; r < truth.rows; ++r) {
    for (int c = 0; c < truth.cols; ++c) {
      const Eigen::Index i = r * truth.cols + c;
      std::snprintf(line, sizeof line, "%d,%d,%.17g,%.17g\n", r, c, run.meanOgf(i), run.meanEp(i));
      out << line;
    }
  }
  return static_cast<bool>(out);
}

struct Options {
  std::string truthPath;
  std::string samplesPath;
  std::string meansOut;
  std::string pngDir;
  unsigned seed = 1;
  std::vector<int> counts = {30, 60, 100, 150, 200, 250, 300, 400, 500, 600};
  double epTolerance = 1e-6;
  double bandedRadius = 0.0;
  bool strict = false;
  std::string logLevel = "info";
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--truth", o.truthPath, "ground truth PGM (dark = occupied); default: the built-in 25x25 world")
      ->check(CLI::ExistingFile);
  app.add_option("--samples", o.samplesPath,
                 "samples CSV with columns row,col,y (y = 1 occupied, -1 free), applied in file order; the "
                 "table then uses prefixes of it and the whole file")
      ->check(CLI::ExistingFile);
  app.add_option("--means-out", o.meansOut, "write row,col,m_ogf,m_ep of the last run to this CSV");
  app.add_option("--png", o.pngDir, "draw the paper's figures into this directory");
  app.add_option("--seed", o.seed, "random seed of the sample draw")->capture_default_str();
  app.add_option("--counts", o.counts, "numbers of samples, one table row each (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--ep-tolerance", o.epTolerance, "EP stops when no site parameter moves more than this")
      ->capture_default_str();
  app.add_option("--banded-radius", o.bandedRadius,
                 "stencil radius R of the banded OGF columns, cells (default: the library's choice from sigma)");
  app.add_flag("--strict", o.strict, "exit with status 1 when a claim of the paper does not hold");
  app.add_option("--log-level", o.logLevel, "trace, debug, info, warn, error")->capture_default_str();
}

// The ground truth, the samples and the table's sample counts (sorted, unique, each one a prefix of the
// samples); false after logging what could not be read.
struct Inputs {
  ogf::paper2d::GroundTruth truth = ogf::paper2d::builtInGroundTruth();
  std::vector<ogf::paper2d::Sample> samples;
  std::vector<int> counts;
};

bool loadInputs(const Options& o, Inputs& in) {
  std::string error;
  if (!o.truthPath.empty() && !ogf::paper2d::loadGroundTruth(o.truthPath, in.truth, error)) {
    spdlog::error("{}", error);
    return false;
  }
  in.counts = o.counts;
  if (!o.samplesPath.empty()) {
    if (!ogf::paper2d::loadSamples(o.samplesPath, in.truth, in.samples, error)) {
      spdlog::error("{}", error);
      return false;
    }
    std::erase_if(in.counts, [&](int n) { return n <= 0 || static_cast<std::size_t>(n) >= in.samples.size(); });
    in.counts.push_back(static_cast<int>(in.samples.size()));
  } else {
    std::erase_if(in.counts, [&](int n) { return n <= 0 || static_cast<std::size_t>(n) > in.truth.cells(); });
    if (in.counts.empty()) {
      spdlog::error("--counts: no count between 1 and {} cells", in.truth.cells());
      return false;
    }
    std::mt19937 rng(o.seed);
    in.samples = ogf::paper2d::drawSamples(
        in.truth, static_cast<std::size_t>(*std::max_element(in.counts.begin(), in.counts.end())), rng);
  }
  std::sort(in.counts.begin(), in.counts.end());
  in.counts.erase(std::unique(in.counts.begin(), in.counts.end()), in.counts.end());
  return true;
}

void printHeader(const Options& o, const Inputs& in, const ogf::paper2d::ExperimentOptions& options) {
  std::printf("# ogf-paper2d: %dx%d ground truth (%s), sigma = %.3g grid unit, r_o/r_f = %.2f/%.2f, %s\n",
              in.truth.rows, in.truth.cols, o.truthPath.empty() ? "built-in" : o.truthPath.c_str(), options.sigma,
              options.occupiedThreshold, options.freeThreshold,
              o.samplesPath.empty() ? ("samples drawn without repetition, seed " + std::to_string(o.seed)).c_str()
                                    : ("samples from " + o.samplesPath).c_str());
  std::printf("%7s %10s %8s %8s %8s %11s %13s %9s\n", "samples", "d(OGF,EP)", "acc(OG)", "acc(EP)", "acc(OGF)",
              "acc(banded)", "d(banded,OGF)", "EP sweeps");
}

// One run per count, each printed as a table row when done; false after logging a run that failed.
bool runTable(const Inputs& in, const ogf::paper2d::ExperimentOptions& options,
              std::vector<ogf::paper2d::ExperimentRun>& runs) {
  std::string error;
  for (int n : in.counts) {
    ogf::paper2d::ExperimentRun run;
    const std::span<const ogf::paper2d::Sample> prefix(in.samples.data(), static_cast<std::size_t>(n));
    if (!ogf::paper2d::runExperiment(in.truth, prefix, options, run, error)) {
      spdlog::error("{} samples: {}", n, error);
      return false;
    }
    if (!run.epConverged) {
      spdlog::warn("{} samples: EP stopped after {} sweeps without converging", n, run.epSweeps);
    }
    std::printf("%7zu %10.4f %8.4f %8.4f %8.4f %11.4f %13.4f %9d\n", run.samples, run.dOgfEp, run.accuracyOg,
                run.accuracyEp, run.accuracyOgf, run.accuracyBanded, run.dBandedOgf, run.epSweeps);
    std::fflush(stdout);
    runs.push_back(std::move(run));
  }
  return true;
}

// The paper's two claims over every row; true when both hold.
bool printClaims(const std::vector<ogf::paper2d::ExperimentRun>& runs) {
  double worstD = 0.0;
  double worstAccGap = 0.0;
  for (const auto& run : runs) {
    worstD = std::max(worstD, run.dOgfEp);
    worstAccGap = std::max(worstAccGap, std::abs(run.accuracyOgf - run.accuracyEp));
  }
  const bool dHolds = worstD < 0.04;
  const bool accHolds = worstAccGap <= 0.01;
  std::printf("claim d(OGF,EP) < 0.04 on every row: %s (largest %.4f)\n", dHolds ? "holds" : "FAILS", worstD);
  std::printf("claim |acc(OGF) - acc(EP)| <= 0.01 on every row: %s (largest %.4f)\n", accHolds ? "holds" : "FAILS",
              worstAccGap);
  return dHolds && accHolds;
}

// --means-out and --png of the last run; false after logging a failed write.
bool writeOutputs(const Options& o, const Inputs& in, const std::vector<ogf::paper2d::ExperimentRun>& runs) {
  const ogf::paper2d::ExperimentRun& last = runs.back();
  if (!o.meansOut.empty() && !writeMeans(o.meansOut, in.truth, last)) {
    spdlog::error("{}: write failed", o.meansOut);
    return false;
  }
  if (!o.pngDir.empty()) {
    std::string error;
    const std::span<const ogf::paper2d::Sample> lastSamples(in.samples.data(), last.samples);
    if (!ogf::paper2d::writeFigures(o.pngDir, in.truth, lastSamples, runs, last, error)) {
      spdlog::error("{}", error);
      return false;
    }
    spdlog::info("figures written to {}", o.pngDir);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Reproduce Sec. VI-A of the OGF paper: d(OGF, EP) and accuracy against the number of samples"};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!ogf::transport::setupLoggingAt("ogf-paper2d", "--log-level", o.logLevel)) return ogf::cli::kExitUsage;

  Inputs in;
  if (!loadInputs(o, in)) return 1;
  ogf::paper2d::ExperimentOptions options;
  options.epTolerance = o.epTolerance;
  options.bandedRadius = o.bandedRadius;
  printHeader(o, in, options);
  std::vector<ogf::paper2d::ExperimentRun> runs;
  if (!runTable(in, options, runs)) return 1;
  const bool claimsHold = printClaims(runs);
  if (!writeOutputs(o, in, runs)) return 1;
  return o.strict && !claimsHold ? kClaimsFailed : 0;
}
