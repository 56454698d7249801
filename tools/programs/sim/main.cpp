// ogf-sim: simulates a VLP-16 on a robot driving through a known world and writes the capture, the
// robot's odometry, the true trajectory and the ground-truth occupancy into one folder (issue 6).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/sim/rig.hpp"
#include "ogf/sim/scene.hpp"
#include "ogf/sim/several_sensors.hpp"
#include "ogf/sim/simulation.hpp"
#include "ogf/transport/logging.hpp"

namespace {

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : "|") + s;
  return out;
}

constexpr const char* kOutputs = R"(
Outputs in --out DIR:
  capture.pcap         VLP-16 capture: classic pcap, Ethernet/IPv4/UDP from 192.168.1.201 to
                       255.255.255.255, data packets to 2368 at the real packet period (1327.104 us,
                       663.552 us dual; HDL-32E 552.96/276.48 us), a position packet (GPRMC, PPS
                       locked) to 8308 after every 14th.
                       Pcap stamps = the packets' TOH time (start 2024-01-01 12:00:00 UTC by default).
  odometry.csv         utime,x,y,z,qw,qx,qy,qz: body pose in the odometry frame at --odometry-rate
                       (utime on the capture's clock; odom frame = world frame at the start).
  odometry.lcmlog      the same as ogf.odometry_t on channel POSE.
  trajectory_true.csv  the true body pose in the world frame, same columns and times.
  truth.grid           ground-truth occupancy at --truth-resolution, cells by the CellKey convention
                       (cell (i,j,k) covers [i r,(i+1) r) x ...): text header (OGF-TRUTH 1, resolution,
                       min_key, size, classes, order x-fastest, fnv1a64, data) then one byte per cell,
                       x fastest: 0 free (open air the sensor's air space reaches), 1 occupied
                       (holds a solid's surface), 2 unobservable (wholly inside a solid, or air
                       sealed off behind surfaces). Reader: ogf::sim::readGroundTruth.
                       truth.grid is the static world: moving solids (--movers) are not in it.
  swept.grid           with --movers: the cells the moving solids passed through, in truth.grid's
                       format and geometry (1 swept, 0 not); ogf-eval reports what a map left there.
  sim.yaml             what was simulated (world, trajectory, sensor, extrinsic sensor->body, counts).
)";

struct Options {
  std::string world = "lab";
  std::string movers = "none";
  std::string trajectory;
  std::string out_dir;
  std::string return_mode = "strongest";
  std::string model_name = "vlp16";
  std::string odometry_error = "none";
  std::string log_level = "info";
  std::string rig;  // --rig: a rig file or preset
  int robots = 0;   // --robots: how many
  ogf::sim::SimulationConfig config;
};

void addOptions(CLI::App& app, Options& o) {
  app.add_option("--world", o.world, "World preset (" + join(ogf::sim::scenePresetNames()) + ") or scene YAML file")
      ->capture_default_str();
  app.add_option("--trajectory", o.trajectory,
                 "A trajectory of the world (static, loop, corridor) or a trajectory YAML file; "
                 "default: the world's default_trajectory");
  app.add_option("--duration", o.config.duration_s, "Seconds of capture")->capture_default_str()->check(ogf::cli::positive());
  app.add_option("--rpm", o.config.sensor.rpm, "Rotation rate, 300..1200 (600 or 1200 typical)")
      ->capture_default_str()
      ->check(ogf::cli::between(300.0, 1200.0));
  app.add_option("--model", o.model_name, "Sensor: vlp16 (the VLP-16 of docs/wire-format.md) or hdl32e")
      ->capture_default_str()
      ->check(CLI::IsMember({"vlp16", "hdl32e"}));
  app.add_option("--return-mode", o.return_mode, "strongest|last|dual")
      ->capture_default_str()
      ->check(CLI::IsMember({"strongest", "last", "dual"}));
  app.add_option("--seed", o.config.sensor.seed, "Seed of every random draw (same seed, same files)")->capture_default_str();
  app.add_option("--out", o.out_dir, "Output folder (created if missing)")->required();
  app.add_option("--range-noise", o.config.sensor.range_noise_m, "Gaussian range noise sigma, metres")
      ->capture_default_str()
      ->check(ogf::cli::nonNegative());
  app.add_option("--dropout", o.config.sensor.dropout, "Probability that a firing returns nothing")
      ->capture_default_str()
      ->check(ogf::cli::between(0.0, 1.0));
  app.add_option("--max-range", o.config.sensor.max_range_m, "Maximum range, metres")
      ->capture_default_str()
      ->check(ogf::cli::between(0.5, 130.0));
  app.add_option("--odometry-error,--odometry-drift", o.odometry_error,
                 "Odometry error preset (" + join(ogf::sim::odometryErrorPresetNames()) +
                     "). Drift presets: wheel-slip = 3 % scale, 0.01 rad/m heading drift, random walks "
                     "0.02 m and 0.005 rad per sqrt(m); gyro-bias = 0.0035 rad/s (0.2 deg/s) heading bias; "
                     "slip-and-bias = both. Random parts follow --seed; trajectory_true.csv never changes")
      ->capture_default_str();
  app.add_option("--odometry-rate", o.config.odometry_rate_hz, "Odometry samples per second")
      ->capture_default_str()
      ->check(ogf::cli::between(1.0, 1000.0));
  app.add_option("--truth-resolution", o.config.truth_resolution_m, "Ground-truth cell size, metres")
      ->capture_default_str()
      ->check(ogf::cli::between(0.02, 5.0));
  app.add_option("--start-utime", o.config.start_utime, "Time of the first firing, us since the epoch")
      ->capture_default_str();
  app.add_option("--movers", o.movers,
                 "Moving solids of the world (e.g. person: someone walking through the lab, then gone), or none; "
                 "the lidar sees them, truth.grid does not; swept.grid marks the cells they passed through")
      ->capture_default_str();
  auto* rig = app.add_option("--rig", o.rig,
                             "Several lidars on the robot: a rig file or a built-in rig (" +
                                 join(ogf::sim::rigPresetNames()) +
                                 "); each sensor on the same drive into --out/<name>/ (its own capture and "
                                 "sim.yaml, the same odometry), listed in --out/rig.yaml");
  app.add_option("--robots", o.robots,
                 "Several robots in the world, each driving one of its trajectories (the default first) into "
                 "--out/robot<k>/, their odometry in the world frame, listed in --out/robots.yaml")
      ->check(CLI::Range(2, 16))->excludes(rig);
  app.add_option("--log-level", o.log_level, "trace|debug|info|warn|error")->capture_default_str();
}

// What is simulated: the scene and the path the robot drives through it.
struct Scenario {
  ogf::sim::Scene scene;
  ogf::sim::TrajectorySpec trajectory;
};

// The scene and its trajectory, with the movers, the sensor and the odometry error put into `o.config`;
// nullopt (after logging which flag was wrong) when one cannot be resolved.
std::optional<Scenario> resolveScenario(Options& o) {
  auto scene = ogf::sim::resolveScene(o.world);
  if (!scene) {
    spdlog::error("--world: {}", scene.error().message);
    return std::nullopt;
  }
  auto spec = ogf::sim::resolveTrajectory(*scene, o.trajectory);
  if (!spec) {
    spdlog::error("--trajectory: {}", spec.error().message);
    return std::nullopt;
  }
  auto moving = ogf::sim::resolveMovers(*scene, o.movers);
  if (!moving) {
    spdlog::error("--movers: {}", moving.error().message);
    return std::nullopt;
  }
  auto& config = o.config;
  config.movers = *moving;
  config.movers_label = o.movers;
  auto model = ogf::sim::odometryErrorPreset(o.odometry_error);
  if (!model) {
    spdlog::error("--odometry-error: {}", model.error().message);
    return std::nullopt;
  }
  config.sensor.mode = *ogf::sim::vlp16::parseReturnMode(o.return_mode);
  config.sensor.model = *ogf::sim::parseLidarModel(o.model_name);
  config.odometry_error = *model;
  config.odometry_error_name = o.odometry_error;
  config.world_label = o.world;
  config.trajectory_label = o.trajectory.empty() ? scene->default_trajectory : o.trajectory;
  return Scenario{std::move(*scene), std::move(*spec)};
}

void logReport(const Options& o, const Scenario& scenario, const ogf::sim::SimulationReport& report, double seconds) {
  const auto& config = o.config;
  spdlog::info("world {} ({} solids), trajectory {} ({:.1f} m path), {} {} s at {} rpm, {} returns",
               scenario.scene.world.name, scenario.scene.world.solids.size(), config.trajectory_label,
               report.path_length_m, ogf::sim::lidarModel(config.sensor.model).name, config.duration_s,
               config.sensor.rpm, o.return_mode);
  spdlog::info("wrote {}: {} data + {} position packets, {} odometry poses (odometry error: {}), truth {}x{}x{} at {} m "
               "({} occupied) in {:.2f} s",
               o.out_dir, report.capture.data_packets, report.capture.position_packets, report.odometry_poses,
               o.odometry_error, report.truth.size[0], report.truth.size[1], report.truth.size[2],
               report.truth.resolution, report.truth.count(ogf::sim::CellClass::Occupied), seconds);
}

// --rig or --robots: each sensor's run logged as one run is.
int simulateSeveral(Options& o, const Scenario& scenario) {
  const auto started = std::chrono::steady_clock::now();
  ogf::Result<std::vector<ogf::sim::SensorRun>> runs = ogf::Error::internal("nothing simulated");
  if (!o.rig.empty()) {
    auto rig = ogf::sim::resolveRig(o.rig);
    if (!rig) {
      spdlog::error("--rig: {}", rig.error().message);
      return EXIT_FAILURE;
    }
    runs = ogf::sim::runRig(scenario.scene, scenario.trajectory, o.config, *rig, o.out_dir);
  } else {
    runs = ogf::sim::runRobots(scenario.scene, o.config, o.robots, o.out_dir);
  }
  if (!runs) {
    spdlog::error("{}", runs.error().message);
    return EXIT_FAILURE;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const std::string base = o.out_dir;
  for (const auto& run : *runs) {
    Options one = o;
    one.out_dir = base + "/" + run.name;
    one.config.trajectory_label = run.trajectory;
    logReport(one, scenario, run.report, seconds / static_cast<double>(runs->size()));
  }
  spdlog::info("wrote {} {} under {} ({})", runs->size(), o.rig.empty() ? "robots" : "sensors", base,
               o.rig.empty() ? "robots.yaml" : "rig.yaml");
  return EXIT_SUCCESS;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ogf-sim: a simulated VLP-16 in a known world, with odometry and ground truth"};
  app.footer(kOutputs);
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (!ogf::transport::setupLoggingAt("ogf-sim", "--log-level", o.log_level)) return EXIT_FAILURE;

  if (o.robots > 0 && !o.trajectory.empty()) {
    spdlog::error("--trajectory: each of --robots drives one of the world's trajectories; give one or the other");
    return EXIT_FAILURE;
  }
  const auto scenario = resolveScenario(o);
  if (!scenario) return EXIT_FAILURE;
  if (!o.rig.empty() || o.robots > 0) return simulateSeveral(o, *scenario);
  const auto started = std::chrono::steady_clock::now();
  auto report = ogf::sim::runSimulation(scenario->scene, scenario->trajectory, o.config, o.out_dir);
  if (!report) {
    spdlog::error("{}", report.error().message);
    return EXIT_FAILURE;
  }
  logReport(o, *scenario, *report, std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
  return EXIT_SUCCESS;
}
