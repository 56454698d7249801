// One simulation run, everything ogf-sim writes into its output folder:
//   capture.pcap          the VLP-16 capture (capture_writer.hpp)
//   odometry.csv          body pose in the odometry frame, utime,x,y,z,qw,qx,qy,qz (pose_files.hpp)
//   odometry.lcmlog       the same as ogf.odometry_t on POSE
//   trajectory_true.csv   the true body pose in the world frame, same columns
//   truth.grid            ground-truth occupancy of the static world (ground_truth.hpp)
//   swept.grid            with moving solids: the cells they passed through (ground_truth.hpp, sweptCells)
//   sim.yaml              what was simulated: world, trajectory, sensor, extrinsic, clock, seed, counts
// The odometry frame starts on the world frame (the first odometry pose is the true one), so with the
// default exact odometry a map built from capture + odometry lines up with truth.grid directly.
#pragma once

#include <cstdint>
#include <string>

#include "ogf/sim/capture_writer.hpp"
#include "ogf/sim/ground_truth.hpp"
#include "ogf/sim/odometry_error.hpp"
#include "ogf/common/result.hpp"
#include "ogf/sim/scene.hpp"
#include "ogf/sim/lidar_simulator.hpp"

namespace ogf::sim {

// 2024-01-01 12:00:00 UTC: a fixed start so every output is reproducible for a seed.
inline constexpr std::int64_t kDefaultStartUtime = 1704110400LL * 1000000LL;

struct SimulationConfig {
  SensorConfig sensor;
  double duration_s = 10.0;
  std::int64_t start_utime = kDefaultStartUtime;
  double odometry_rate_hz = 100.0;
  std::string odometry_error_name = "none";
  OdometryErrorModel odometry_error;
  double truth_resolution_m = 0.2;
  std::string world_label;       // how the world was named (preset or path), for sim.yaml
  std::string trajectory_label;  // likewise for the trajectory
  std::vector<MovingSolidSpec> movers;  // moving solids the lidar sees (none by default)
  std::string movers_label;             // their set's name, for sim.yaml
};

struct SimulationReport {
  CaptureSummary capture;
  std::size_t odometry_poses = 0;
  GroundTruth truth;  // kept so the caller can report counts
  std::size_t swept_cells = 0;  // cells moving solids passed through (swept.grid)
  double path_length_m = 0.0;
};

// Writes every output into `out_dir` (created if missing).
Result<SimulationReport> runSimulation(const Scene& scene, const TrajectorySpec& trajectory,
                                       const SimulationConfig& config, const std::string& out_dir);

}  // namespace ogf::sim
