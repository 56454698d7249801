// A rig: the lidars one robot carries, each with its name, model, rate and mount on the body. ogf-sim
// --rig simulates each of them on the same drive through the same world, each into a capture of its own.
//
// Rig file (YAML):
//   sensors:
//     - {name: front, model: vlp16, rpm: 600, mount: {xyz: [0.5, 0, 0.4], rpy_deg: [0, 0, 0]}}
//     - {name: rear, mount: {xyz: [-0.5, 0, 1.4], rpy_deg: [0, 15, 180]}}   # model, rpm: ogf-sim's flags
// mount: sensor -> body, metres; rpy_deg as a scene's sensor_mount, R = Rz(yaw) Ry(pitch) Rx(roll) (a
// positive pitch turns the sensor's x axis down).
#pragma once

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf::sim {

struct RigSensor {
  std::string name;                  // 1 to 32 of [A-Za-z0-9_-], unique in the rig: its folder's name
  std::optional<std::string> model;  // "vlp16" or "hdl32e"; unset: --model
  std::optional<double> rpm;         // 300..1200; unset: --rpm
  Eigen::Isometry3d sensor_to_body = Eigen::Isometry3d::Identity();
};

struct Rig {
  std::vector<RigSensor> sensors;  // at least one
};

// Parses a rig file's text; `source` names it in errors ("rig.yaml:4: sensors[1].mount.xyz: expected 3
// numbers").
Result<Rig> parseRig(std::string_view yaml, const std::string& source);

// The built-in rigs: "front-rear", two VLP-16s, one low at the front looking ahead, one high at the back
// turned round and tilted down, so each sees what the other does not.
std::vector<std::string> rigPresetNames();

// The rig named by --rig: a built-in name, else a rig file's path.
Result<Rig> resolveRig(const std::string& preset_or_path);

}  // namespace ogf::sim
