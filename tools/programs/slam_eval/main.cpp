// ogf-slam-eval: scores a SLAM result log on the Freiburg 2-D SLAM benchmark (Kümmerle et al. 2009, the
// metricEvaluator definition, docs/test-data.md §3.4). The trajectory is the robot pose
// of every laser record (FLASER's second triple, ROBOTLASER1's robot_pose) at its ipc_timestamp; each
// relation's two stamps take the nearest pose within --tolerance. This file owns the command line, the
// files and the exit code; the metric is in ogf::slam_io.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <string>

#include "ogf/common/command_line.hpp"
#include "ogf/slam_io/laser_trajectory.hpp"
#include "ogf/slam_io/relations.hpp"

namespace {

using ogf::cli::kExitOk;
constexpr int kExitFailed = 1;  // an input could not be read, or no relation matched
using ogf::cli::kExitUsage;  // bad flags or configuration
constexpr std::size_t kMalformedShown = 10;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Scores a SLAM result log against the benchmark's ground-truth relations (Kuemmerle et al. 2009).\n"
      "Per relation (t1, t2, reference motion): the result poses nearest to t1 and t2 (within --tolerance), "
      "their\n"
      "motion T(t1)^-1 T(t2), and its component-wise difference from the reference, angle normalised:\n"
      "  trans = sqrt(dx^2 + dy^2) in metres, rot = |dyaw| in degrees;\n"
      "printed as mean ± sample standard deviation (N-1), and the maximum translational error:\n"
      "  trans <mean> ± <std> m max <max>\n"
      "  rot <mean> ± <std> deg\n"
      "  relations <matched> matched, <unmatched> unmatched of <total>; rot max <max> deg\n"
      "  sqr trans <mean> ± <std> m^2, sqr rot <mean> ± <std> deg^2   (the squared errors, as tables also "
      "give)\n"
      "Exit 0 when scored, 1 when a file is unreadable or no relation matched, 2 on bad flags."};
  std::string result_path, relations_path;
  double tolerance = 0.1;  // metricEvaluator's g_MaxTimeRelationToSlam
  app.add_option(
         "--result", result_path,
         "CARMEN result log: every laser record with the estimated robot pose and its original ipc_timestamp")
      ->required();
  app.add_option("--relations", relations_path, "Ground-truth relations file (t1 t2 x y z roll pitch yaw)")
      ->required();
  app.add_option("--tolerance", tolerance, "Largest gap between a relation stamp and its pose, seconds")
      ->capture_default_str()
      ->check(ogf::cli::positive());
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  std::ifstream result_in(result_path);
  if (!result_in) {
    std::fprintf(stderr, "ogf-slam-eval: --result: cannot open '%s'\n", result_path.c_str());
    return kExitFailed;
  }
  const auto trajectory = ogf::slam_io::readLaserTrajectory(result_in, result_path);
  if (result_in.bad()) {
    std::fprintf(stderr, "ogf-slam-eval: --result: read error in '%s'\n", result_path.c_str());
    return kExitFailed;
  }
  for (std::size_t i = 0; i < trajectory.malformed.size() && i < kMalformedShown; ++i) {
    std::fprintf(stderr, "ogf-slam-eval: skipped %s\n", trajectory.malformed[i].message.c_str());
  }
  if (trajectory.malformed.size() > kMalformedShown) {
    std::fprintf(stderr, "ogf-slam-eval: skipped %zu malformed lines in all\n", trajectory.malformed.size());
  }
  if (trajectory.poses.empty()) {
    std::fprintf(stderr,
                 "ogf-slam-eval: --result: '%s' holds no FLASER or ROBOTLASER1 record (%zu lines read)\n",
                 result_path.c_str(), trajectory.lines_read);
    return kExitFailed;
  }

  std::ifstream relations_in(relations_path);
  if (!relations_in) {
    std::fprintf(stderr, "ogf-slam-eval: --relations: cannot open '%s'\n", relations_path.c_str());
    return kExitFailed;
  }
  const auto relations = ogf::slam_io::readRelations(relations_in, relations_path);
  if (!relations) {
    std::fprintf(stderr, "ogf-slam-eval: --relations: %s\n", relations.error().message.c_str());
    return kExitFailed;
  }
  if (relations->empty()) {
    std::fprintf(stderr, "ogf-slam-eval: --relations: '%s' holds no relation\n", relations_path.c_str());
    return kExitFailed;
  }

  const auto metric = ogf::slam_io::evaluateRelations(trajectory.poses, *relations, tolerance);
  if (metric.translation.count == 0) {
    std::fprintf(
        stderr,
        "ogf-slam-eval: no relation matched: none of the %zu relations has result poses within %g s of both "
        "stamps (result stamps %.6f .. %.6f)\n",
        relations->size(), tolerance, trajectory.poses.front().t, trajectory.poses.back().t);
    return kExitFailed;
  }
  std::printf("trans %.4f ± %.4f m max %.4f\n", metric.translation.mean, metric.translation.std,
              metric.translation.max);
  std::printf("rot %.4f ± %.4f deg\n", metric.rotation_deg.mean, metric.rotation_deg.std);
  std::printf("relations %zu matched, %zu unmatched of %zu; rot max %.4f deg\n", metric.translation.count,
              metric.unmatched, relations->size(), metric.rotation_deg.max);
  std::printf("sqr trans %.4f ± %.4f m^2, sqr rot %.4f ± %.4f deg^2\n", metric.translation_squared.mean,
              metric.translation_squared.std, metric.rotation_squared_deg.mean,
              metric.rotation_squared_deg.std);
  if (metric.unmatched > 0) {
    std::fprintf(stderr, "ogf-slam-eval: %zu of %zu relations had no result pose within %g s of a stamp\n",
                 metric.unmatched, relations->size(), tolerance);
  }
  return kExitOk;
}
