// A scene: the world, where the lidar sits on the body, and the named trajectories that suit the world.
// Read from a YAML scene file or one of the built-in presets (tools/lib/sim/presets/*.yaml, compiled in).
//
// Scene file (YAML; lengths in metres, angles in degrees):
//   name: lab
//   bounds: {min: [x, y, z], max: [x, y, z]}   # ground-truth region; default: the solids' box + 1 m
//   materials:                                 # 'default' (reflectivity 50) always exists
//     - {name: glass, reflectivity: 20, transmittance: 0.6}
//   ground: {height: 0, material: floor}       # optional: the half-space z <= height
//   solids:
//     - {type: box, center: [x, y, z], size: [sx, sy, sz], yaw_deg: 0, material: wall}
//     - {type: cylinder, center: [x, y], radius: r, z: [z_min, z_max], material: metal}
//     - {type: plane, point: [x, y, z], normal: [nx, ny, nz], material: wall}   # solid behind the normal
//   sensor_mount: {xyz: [0, 0, 1.0], rpy_deg: [0, 0, 0]}   # sensor → body; default level, 1 m up
//   trajectories:                              # names usable as --trajectory
//     static: {waypoints: [[x, y]], yaw_deg: 0}
//     loop: {speed: 1.0, loop: true, waypoints: [[x, y], [x, y, z], ...]}
//   default_trajectory: loop
//   movers:                                    # named sets of moving solids, usable as --movers
//     person:
//       - {type: cylinder, center: [0, 0], radius: 0.25, z: [0, 1.75], material: skin, start_s: 2,
//          path: {speed: 1.2, waypoints: [[x, y], ...]}}   # shape in its own frame; gone at the path's end
// A trajectory file holds one trajectory entry at its top level ({speed, loop, waypoints, yaw_deg}).
#pragma once

#include <Eigen/Geometry>

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/sim/trajectory.hpp"
#include "ogf/sim/world.hpp"

namespace ogf::sim {

struct Scene {
  World world;
  Eigen::Isometry3d sensor_to_body = Eigen::Isometry3d::Identity();
  std::map<std::string, TrajectorySpec> trajectories;
  std::string default_trajectory;
  std::map<std::string, std::vector<MovingSolidSpec>> movers;
};

// Parses scene YAML; `source` names it in errors ("lab.yaml:12: solids[3].radius: must be positive").
Result<Scene> parseScene(std::string_view yaml, const std::string& source);
Result<Scene> loadSceneFile(const std::string& path);

// Parses one trajectory (the entry schema above) from YAML text or a file.
Result<TrajectorySpec> parseTrajectory(std::string_view yaml, const std::string& source);
Result<TrajectorySpec> loadTrajectoryFile(const std::string& path);

// The built-in worlds: "lab" (the default: a small room that maps quickly), "warehouse", "street".
std::vector<std::string> scenePresetNames();
Result<Scene> presetScene(const std::string& name);

// The scene named by --world: a preset name, else a YAML file path.
Result<Scene> resolveScene(const std::string& preset_or_path);
// The moving solids named by --movers: a set of the scene's, or none for "" and "none".
Result<std::vector<MovingSolidSpec>> resolveMovers(const Scene& scene, const std::string& name);
// The trajectory named by --trajectory: one of the scene's named trajectories, else a YAML file path; an
// empty name means the scene's default_trajectory.
Result<TrajectorySpec> resolveTrajectory(const Scene& scene, const std::string& name_or_path);

}  // namespace ogf::sim
