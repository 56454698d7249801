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

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Reproduce Sec. VI-A of the OGF paper: d(OGF, EP) and accuracy against the number of samples"};
  std::string truthPath;
  std::string samplesPath;
  std::string meansOut;
  std::string pngDir;
  unsigned seed = 1;
  std::vector<int> counts = {30, 60, 100, 150, 200, 250, 300, 400, 500, 600};
  double epTolerance = 1e-6;
  bool strict = false;
  std::string logLevel = "info";
  app.add_option("--truth", truthPath, "ground truth PGM (dark = occupied); default: the built-in 25x25 world")
      ->check(CLI::ExistingFile);
  app.add_option("--samples", samplesPath,
                 "samples CSV with columns row,col,y (y = 1 occupied, -1 free), applied in file order; the "
                 "table then uses prefixes of it and the whole file")
      ->check(CLI::ExistingFile);
  app.add_option("--means-out", meansOut, "write row,col,m_ogf,m_ep of the last run to this CSV");
  app.add_option("--png", pngDir, "draw the paper's figures into this directory");
  app.add_option("--seed", seed, "random seed of the sample draw")->capture_default_str();
  app.add_option("--counts", counts, "numbers of samples, one table row each (comma-separated)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--ep-tolerance", epTolerance, "EP stops when no site parameter moves more than this")
      ->capture_default_str();
  double bandedRadius = 0.0;
  app.add_option("--banded-radius", bandedRadius,
                 "stencil radius R of the banded OGF columns, cells (default: the library's choice from sigma)");
  app.add_flag("--strict", strict, "exit with status 1 when a claim of the paper does not hold");
  app.add_option("--log-level", logLevel, "trace, debug, info, warn, error")->capture_default_str();
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  if (!ogf::transport::setupLoggingAt("ogf-paper2d", "--log-level", logLevel)) return ogf::cli::kExitUsage;

  ogf::paper2d::GroundTruth truth = ogf::paper2d::builtInGroundTruth();
  std::string error;
  if (!truthPath.empty() && !ogf::paper2d::loadGroundTruth(truthPath, truth, error)) {
    spdlog::error("{}", error);
    return 1;
  }
  std::vector<ogf::paper2d::Sample> samples;
  if (!samplesPath.empty()) {
    if (!ogf::paper2d::loadSamples(samplesPath, truth, samples, error)) {
      spdlog::error("{}", error);
      return 1;
    }
    std::erase_if(counts, [&](int n) { return n <= 0 || static_cast<std::size_t>(n) >= samples.size(); });
    counts.push_back(static_cast<int>(samples.size()));
  } else {
    std::erase_if(counts, [&](int n) { return n <= 0 || static_cast<std::size_t>(n) > truth.cells(); });
    if (counts.empty()) {
      spdlog::error("--counts: no count between 1 and {} cells", truth.cells());
      return 1;
    }
    std::mt19937 rng(seed);
    samples = ogf::paper2d::drawSamples(truth, static_cast<std::size_t>(*std::max_element(counts.begin(), counts.end())), rng);
  }
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());

  ogf::paper2d::ExperimentOptions options;
  options.epTolerance = epTolerance;
  options.bandedRadius = bandedRadius;
  std::printf("# ogf-paper2d: %dx%d ground truth (%s), sigma = %.3g grid unit, r_o/r_f = %.2f/%.2f, %s\n",
              truth.rows, truth.cols, truthPath.empty() ? "built-in" : truthPath.c_str(), options.sigma,
              options.occupiedThreshold, options.freeThreshold,
              samplesPath.empty() ? ("samples drawn without repetition, seed " + std::to_string(seed)).c_str()
                                  : ("samples from " + samplesPath).c_str());
  std::printf("%7s %10s %8s %8s %8s %11s %13s %9s\n", "samples", "d(OGF,EP)", "acc(OG)", "acc(EP)", "acc(OGF)",
              "acc(banded)", "d(banded,OGF)", "EP sweeps");
  std::vector<ogf::paper2d::ExperimentRun> runs;
  double worstD = 0.0;
  double worstAccGap = 0.0;
  for (int n : counts) {
    ogf::paper2d::ExperimentRun run;
    const std::span<const ogf::paper2d::Sample> prefix(samples.data(), static_cast<std::size_t>(n));
    if (!ogf::paper2d::runExperiment(truth, prefix, options, run, error)) {
      spdlog::error("{} samples: {}", n, error);
      return 1;
    }
    if (!run.epConverged) {
      spdlog::warn("{} samples: EP stopped after {} sweeps without converging", n, run.epSweeps);
    }
    std::printf("%7zu %10.4f %8.4f %8.4f %8.4f %11.4f %13.4f %9d\n", run.samples, run.dOgfEp, run.accuracyOg,
                run.accuracyEp, run.accuracyOgf, run.accuracyBanded, run.dBandedOgf, run.epSweeps);
    std::fflush(stdout);
    worstD = std::max(worstD, run.dOgfEp);
    worstAccGap = std::max(worstAccGap, std::abs(run.accuracyOgf - run.accuracyEp));
    runs.push_back(std::move(run));
  }
  const bool dHolds = worstD < 0.04;
  const bool accHolds = worstAccGap <= 0.01;
  std::printf("claim d(OGF,EP) < 0.04 on every row: %s (largest %.4f)\n", dHolds ? "holds" : "FAILS", worstD);
  std::printf("claim |acc(OGF) - acc(EP)| <= 0.01 on every row: %s (largest %.4f)\n", accHolds ? "holds" : "FAILS",
              worstAccGap);

  const ogf::paper2d::ExperimentRun& last = runs.back();
  if (!meansOut.empty() && !writeMeans(meansOut, truth, last)) {
    spdlog::error("{}: write failed", meansOut);
    return 1;
  }
  if (!pngDir.empty()) {
    const std::span<const ogf::paper2d::Sample> lastSamples(samples.data(), last.samples);
    if (!ogf::paper2d::writeFigures(pngDir, truth, lastSamples, runs, last, error)) {
      spdlog::error("{}", error);
      return 1;
    }
    spdlog::info("figures written to {}", pngDir);
  }
  return strict && !(dHolds && accHolds) ? kClaimsFailed : 0;
}
