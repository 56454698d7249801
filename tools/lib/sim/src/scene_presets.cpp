// The built-in scenes and the --world / --trajectory lookup: a preset name first, then a file path.
#include <filesystem>

#include "ogf/sim/scene.hpp"
#include "preset_texts.hpp"

namespace ogf::sim {

std::vector<std::string> scenePresetNames() {
  std::vector<std::string> names;
  for (const auto& p : detail::presetTexts()) names.emplace_back(p.name);
  return names;
}

Result<Scene> presetScene(const std::string& name) {
  for (const auto& p : detail::presetTexts()) {
    if (p.name == name) return parseScene(p.yaml, "preset " + name);
  }
  std::string known;
  for (const auto& n : scenePresetNames()) known += (known.empty() ? "" : ", ") + n;
  return Error{"no world preset named '" + name + "' (presets: " + known + ")"};
}

Result<Scene> resolveScene(const std::string& preset_or_path) {
  for (const auto& p : detail::presetTexts()) {
    if (p.name == preset_or_path) return presetScene(preset_or_path);
  }
  if (!std::filesystem::exists(preset_or_path)) {
    return presetScene(preset_or_path);  // neither: the error lists the presets
  }
  return loadSceneFile(preset_or_path);
}

Result<std::vector<MovingSolidSpec>> resolveMovers(const Scene& scene, const std::string& name) {
  if (name.empty() || name == "none") return std::vector<MovingSolidSpec>{};
  if (const auto it = scene.movers.find(name); it != scene.movers.end()) return it->second;
  std::string known = "none";
  for (const auto& [n, set] : scene.movers) known += ", " + n;
  return Error{"world '" + scene.world.name + "' has no moving solids named '" + name + "' (" + known + ")"};
}

Result<TrajectorySpec> resolveTrajectory(const Scene& scene, const std::string& name_or_path) {
  const std::string name = name_or_path.empty() ? scene.default_trajectory : name_or_path;
  if (const auto it = scene.trajectories.find(name); it != scene.trajectories.end()) return it->second;
  if (std::filesystem::exists(name)) return loadTrajectoryFile(name);
  std::string known;
  for (const auto& [n, spec] : scene.trajectories) known += (known.empty() ? "" : ", ") + n;
  return Error{"'" + name + "' is neither a trajectory of world '" + scene.world.name +
               "' (" + known + ") nor a file"};
}

}  // namespace ogf::sim
