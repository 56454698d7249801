// Several lidars in one simulated world (several_sensors.hpp).
#include "ogf/sim/several_sensors.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "ogf/sim/lidar_model.hpp"

namespace ogf::sim {
namespace {

std::string mountYaml(const Eigen::Isometry3d& m) {
  const Eigen::Vector3d t = m.translation();
  const Eigen::Quaterniond q(m.linear());
  return fmt::format("{{xyz: [{}, {}, {}], quaternion_wxyz: [{}, {}, {}, {}]}}", t.x(), t.y(), t.z(), q.w(), q.x(),
                     q.y(), q.z());
}

// rig.yaml or robots.yaml: `header` (a comment), then `key`: the runs.
Status writeListing(const std::string& path, const std::string& header, const std::string& key,
                    const std::vector<SensorRun>& runs) {
  std::ofstream out(path);
  out << header << key << ":\n";
  for (const auto& r : runs)
    out << fmt::format("  - {{name: {}, folder: {}, trajectory: {}, sensor_to_body: {}}}\n", r.name, r.name,
                       r.trajectory, mountYaml(r.sensor_to_body));
  if (!out) return Error::io(path + ": cannot write");
  return okStatus();
}

}  // namespace

Result<std::vector<SensorRun>> runRig(const Scene& scene, const TrajectorySpec& trajectory, const SimulationConfig& config,
                                      const Rig& rig, const std::string& out_dir) {
  std::vector<SensorRun> runs;
  for (const RigSensor& sensor : rig.sensors) {
    Scene mounted = scene;
    mounted.sensor_to_body = sensor.sensor_to_body;
    SimulationConfig c = config;
    if (sensor.model) c.sensor.model = *parseLidarModel(*sensor.model);
    if (sensor.rpm) c.sensor.rpm = *sensor.rpm;
    auto report = runSimulation(mounted, trajectory, c, (std::filesystem::path(out_dir) / sensor.name).string());
    if (!report) return report.error().within("sensor " + sensor.name);
    runs.push_back({sensor.name, config.trajectory_label, sensor.sensor_to_body, std::move(*report)});
  }
  const auto listed = writeListing((std::filesystem::path(out_dir) / "rig.yaml").string(),
                                   "# ogf-sim --rig: the sensors of one robot, one folder each (same drive, same odometry).\n",
                                   "sensors", runs);
  if (!listed) return listed.error();
  return runs;
}

Result<std::vector<std::string>> robotTrajectories(const Scene& scene, int robots) {
  std::vector<std::string> moving;
  const auto drives = [&](const std::string& name) {
    const auto it = scene.trajectories.find(name);
    return it != scene.trajectories.end() && it->second.waypoints.size() > 1;
  };
  if (drives(scene.default_trajectory)) moving.push_back(scene.default_trajectory);
  for (const auto& [name, spec] : scene.trajectories)
    if (name != scene.default_trajectory && drives(name)) moving.push_back(name);
  if (moving.empty()) return Error::configuration("the world has no trajectory that moves: robots need one");
  std::vector<std::string> chosen;
  for (int k = 0; k < robots; ++k) chosen.push_back(moving[static_cast<std::size_t>(k) % moving.size()]);
  return chosen;
}

Result<std::vector<SensorRun>> runRobots(const Scene& scene, const SimulationConfig& config, int robots,
                                         const std::string& out_dir) {
  auto trajectories = robotTrajectories(scene, robots);
  if (!trajectories) return trajectories.error();
  std::vector<SensorRun> runs;
  for (int k = 1; k <= robots; ++k) {
    const std::string& name = (*trajectories)[static_cast<std::size_t>(k - 1)];
    auto spec = resolveTrajectory(scene, name);
    if (!spec) return spec.error();
    SimulationConfig c = config;
    c.sensor.seed = config.sensor.seed + static_cast<std::uint64_t>(k - 1);
    c.trajectory_label = name;
    const std::string robot = "robot" + std::to_string(k);
    auto report = runSimulation(scene, *spec, c, (std::filesystem::path(out_dir) / robot).string());
    if (!report) return report.error().within(robot);
    runs.push_back({robot, name, scene.sensor_to_body, std::move(*report)});
  }
  const auto listed = writeListing((std::filesystem::path(out_dir) / "robots.yaml").string(),
                                   "# ogf-sim --robots: one folder a robot; every odometry is in the world frame.\n",
                                   "robots", runs);
  if (!listed) return listed.error();
  return runs;
}

}  // namespace ogf::sim
