// Several lidars in one simulated world: the sensors of a rig on one robot (each on the same drive, each into
// a capture of its own), or several robots each driving one of the world's trajectories. Each sensor's
// folder under the run's is a complete single-sensor run (capture.pcap, odometry, truth, sim.yaml with its
// own sensor_to_body), so every program that reads one reads it; rig.yaml or robots.yaml beside them lists
// them. The odometry of every run is in the world frame (odom = world at the start), so the robots share
// one frame as a localisation system would give it.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/sim/rig.hpp"
#include "ogf/sim/scene.hpp"
#include "ogf/sim/simulation.hpp"

namespace ogf::sim {

struct SensorRun {
  std::string name;        // the sensor's (rig) or the robot's (robots) name: its folder under the run's
  std::string trajectory;  // the trajectory it drove
  Eigen::Isometry3d sensor_to_body = Eigen::Isometry3d::Identity();
  SimulationReport report;
};

// Every sensor of `rig` on `trajectory` with `config` (the sensor's model and rpm over config's), its mount
// over the scene's, into out_dir/<name>/; then out_dir/rig.yaml. Every sensor gets config's seed, so the
// odometry files are identical.
Result<std::vector<SensorRun>> runRig(const Scene& scene, const TrajectorySpec& trajectory, const SimulationConfig& config,
                                      const Rig& rig, const std::string& out_dir);

// The trajectories robots 1..n drive: the scene's default first, then its others in name order, leaving out
// those of a single waypoint (a robot standing still); cycled when there are fewer than n.
Result<std::vector<std::string>> robotTrajectories(const Scene& scene, int robots);

// `robots` robots, robot k on robotTrajectories()[k - 1] with seed config's + k - 1, into
// out_dir/robot<k>/; then out_dir/robots.yaml.
Result<std::vector<SensorRun>> runRobots(const Scene& scene, const SimulationConfig& config, int robots,
                                         const std::string& out_dir);

}  // namespace ogf::sim
