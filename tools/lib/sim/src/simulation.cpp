// A whole run: capture, odometry, true trajectory, ground truth and a description of the run.
#include "ogf/sim/simulation.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "ogf/sim/pose_files.hpp"

namespace ogf::sim {
namespace {

Status writeDescription(const std::string& path, const Scene& scene, const SimulationConfig& config,
                        const SimulationReport& report) {
  std::ofstream out(path);
  if (!out) return Error{path + ": cannot create"};
  const Eigen::Vector3d t = scene.sensor_to_body.translation();
  const Eigen::Quaterniond q(scene.sensor_to_body.linear());
  out << "# ogf-sim run: what the files beside this one were made from.\n"
      << fmt::format("world: {}\nworld_name: {}\ntrajectory: {}\n", config.world_label, scene.world.name,
                     config.trajectory_label)
      << fmt::format("duration_s: {}\nstart_utime: {}\nseed: {}\n", config.duration_s, config.start_utime,
                     config.sensor.seed)
      << fmt::format("sensor: {{model: {}, rpm: {}, return_mode: {}, range_noise_m: {}, dropout: {}, "
                     "max_range_m: {}}}\n",
                     lidarModel(config.sensor.model).name, config.sensor.rpm, vlp16::toString(config.sensor.mode), config.sensor.range_noise_m,
                     config.sensor.dropout, config.sensor.max_range_m)
      << fmt::format("sensor_to_body: {{xyz: [{}, {}, {}], quaternion_wxyz: [{}, {}, {}, {}]}}\n", t.x(), t.y(),
                     t.z(), q.w(), q.x(), q.y(), q.z())
      << fmt::format("odometry: {{rate_hz: {}, error: {}, frame: odom (= world at the start)}}\n",
                     config.odometry_rate_hz, config.odometry_error_name)
      << fmt::format("capture: {{data_packets: {}, position_packets: {}, first_utime: {}, last_utime: {}}}\n",
                     report.capture.data_packets, report.capture.position_packets, report.capture.first_utime,
                     report.capture.last_utime)
      << fmt::format("movers: {{set: {}, count: {}, swept_cells: {}}}\n", config.movers_label.empty() ? "none" : config.movers_label,
                     config.movers.size(), report.swept_cells)
      << fmt::format("truth: {{file: truth.grid, resolution: {}, occupied: {}, free: {}, unobservable: {}}}\n",
                     report.truth.resolution, report.truth.count(CellClass::Occupied),
                     report.truth.count(CellClass::Free), report.truth.count(CellClass::Unobservable));
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Ok{};
}

}  // namespace

Result<SimulationReport> runSimulation(const Scene& scene, const TrajectorySpec& spec, const SimulationConfig& config,
                                       const std::string& out_dir) {
  if (!(config.duration_s > 0.0)) return Error{"duration must be positive"};
  if (!(config.odometry_rate_hz > 0.0)) return Error{"odometry rate must be positive"};
  if (!(config.truth_resolution_m > 0.0)) return Error{"truth resolution must be positive"};
  if (config.sensor.rpm < 300.0 || config.sensor.rpm > 1200.0) return Error{"rpm must be in 300..1200 (VLP-16)"};
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) return Error{out_dir + ": cannot create: " + ec.message()};
  const std::filesystem::path dir(out_dir);

  auto trajectory = Trajectory::build(spec);
  if (!trajectory) return Error{trajectory.error().message};
  SimulationReport report;
  report.path_length_m = trajectory->length();

  World world = scene.world;
  for (const MovingSolidSpec& moverSpec : config.movers) {
    auto mover = MovingSolid::build(moverSpec);
    if (!mover) return Error{"moving solid: " + mover.error().message};
    world.movers.push_back(std::move(*mover));
  }
  const LidarSimulator sim(world, scene.sensor_to_body, *trajectory, config.sensor, config.start_utime);
  auto capture = writeCapture(sim, config.duration_s, (dir / "capture.pcap").string());
  if (!capture) return Error{capture.error().message};
  report.capture = *capture;

  // Poses from the start through the end of the last packet, at the odometry rate, on the capture clock.
  const auto period_us = static_cast<std::int64_t>(std::llround(1e6 / config.odometry_rate_hz));
  const std::int64_t end_us =
      (sim.packetStartNs(capture->data_packets) + 999) / 1000;  // covers every firing of the last packet
  std::vector<StampedPose> truth;
  for (std::int64_t u = 0; u <= end_us + period_us - 1; u += period_us) {
    truth.push_back(StampedPose{config.start_utime + u, trajectory->poseAt(static_cast<double>(u) * 1e-6)});
  }
  const auto odometry = simulateOdometry(truth, config.odometry_error, config.sensor.seed);
  report.odometry_poses = odometry.size();
  if (auto s = writePoseCsv((dir / "trajectory_true.csv").string(), truth); !s) return Error{s.error().message};
  if (auto s = writePoseCsv((dir / "odometry.csv").string(), odometry); !s) return Error{s.error().message};
  if (auto s = writeOdometryLcmLog((dir / "odometry.lcmlog").string(), odometry); !s) return Error{s.error().message};

  // The open air the sensor reaches is seeded from where the sensor was at every pose.
  std::vector<Eigen::Vector3d> sensor_positions;
  sensor_positions.reserve(truth.size());
  for (const auto& p : truth) sensor_positions.push_back((p.pose.isometry() * scene.sensor_to_body).translation());
  report.truth = computeGroundTruth(scene.world, config.truth_resolution_m, sensor_positions);
  if (auto s = writeGroundTruth((dir / "truth.grid").string(), report.truth); !s) return Error{s.error().message};
  if (!world.movers.empty()) {
    const GroundTruth swept = sweptCells(world, report.truth, config.duration_s);
    report.swept_cells = swept.count(CellClass::Occupied);
    if (auto s = writeGroundTruth((dir / "swept.grid").string(), swept); !s) return Error{s.error().message};
  }
  if (auto s = writeDescription((dir / "sim.yaml").string(), scene, config, report); !s) return Error{s.error().message};
  return report;
}

}  // namespace ogf::sim
