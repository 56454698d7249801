// Reads scene and trajectory YAML (schema in scene.hpp). Every refusal names the source, the line and the
// field, so a typo in a hand-written world is found in one look.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>

#include "ogf/sim/scene.hpp"

#include "units.hpp"

namespace ogf::sim {
namespace {

class Parser {
 public:
  explicit Parser(std::string source) : source_(std::move(source)) {}

  Error error(const YAML::Node& node, const std::string& field, const std::string& what) const {
    std::string where = source_;
    if (node.IsDefined() && node.Mark().line >= 0) where += ":" + std::to_string(node.Mark().line + 1);
    return Error::configuration(where + ": " + field + ": " + what);
  }

  // A number at parent[key]; `fallback` when absent (nullopt: required).
  Result<double> number(const YAML::Node& parent, const std::string& key, const std::string& path,
                        std::optional<double> fallback) const {
    const YAML::Node node = parent[key];
    if (!node.IsDefined() || node.IsNull()) {
      if (fallback) return *fallback;
      return error(parent, path + key, "missing");
    }
    double v = 0.0;
    if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || !std::isfinite(v)) {
      return error(node, path + key, "expected a number, got '" + (node.IsScalar() ? node.Scalar() : "?") + "'");
    }
    return v;
  }

  // A list of exactly `n` numbers (or n_min..n when n_min < n; missing entries are `pad`).
  Result<Eigen::VectorXd> vector(const YAML::Node& parent, const std::string& key, const std::string& path,
                                 int n_min, int n, double pad = 0.0) const {
    const YAML::Node node = parent[key];
    if (!node.IsDefined() || node.IsNull()) return error(parent, path + key, "missing");
    return vectorNode(node, path + key, n_min, n, pad);
  }

  Result<Eigen::VectorXd> vectorNode(const YAML::Node& node, const std::string& field, int n_min, int n,
                                     double pad = 0.0) const {
    const std::string want = n_min == n ? std::to_string(n) : std::to_string(n_min) + " to " + std::to_string(n);
    if (!node.IsSequence() || static_cast<int>(node.size()) < n_min || static_cast<int>(node.size()) > n) {
      return error(node, field, "expected a list of " + want + " numbers");
    }
    Eigen::VectorXd v = Eigen::VectorXd::Constant(n, pad);
    for (std::size_t i = 0; i < node.size(); ++i) {
      double x = 0.0;
      if (!node[i].IsScalar() || !YAML::convert<double>::decode(node[i], x) || !std::isfinite(x)) {
        return error(node[i], field + "[" + std::to_string(i) + "]", "expected a number");
      }
      v[static_cast<Eigen::Index>(i)] = x;
    }
    return v;
  }

  Result<std::string> string(const YAML::Node& parent, const std::string& key, const std::string& path,
                             std::optional<std::string> fallback) const {
    const YAML::Node node = parent[key];
    if (!node.IsDefined() || node.IsNull()) {
      if (fallback) return *fallback;
      return error(parent, path + key, "missing");
    }
    if (!node.IsScalar()) return error(node, path + key, "expected a string");
    return node.Scalar();
  }

  Result<bool> boolean(const YAML::Node& parent, const std::string& key, const std::string& path,
                       bool fallback) const {
    const YAML::Node node = parent[key];
    if (!node.IsDefined() || node.IsNull()) return fallback;
    bool b = false;
    if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b)) {
      return error(node, path + key, "expected true or false");
    }
    return b;
  }

  // Refuses keys outside `allowed`, so a misspelt field is not silently ignored.
  std::optional<Error> onlyKeys(const YAML::Node& map, const std::string& path,
                                std::initializer_list<const char*> allowed,
                                std::initializer_list<const char*> also = {}) const {
    if (!map.IsMap()) return error(map, path.empty() ? "(top level)" : path, "expected a mapping");
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      bool known = false;
      for (const char* a : allowed) known = known || key == a;
      for (const char* a : also) known = known || key == a;
      if (!known) return error(kv.first, path + key, "unknown field");
    }
    return std::nullopt;
  }

  Result<TrajectorySpec> trajectory(const YAML::Node& node, const std::string& path) const {
    if (auto e = onlyKeys(node, path, {"waypoints", "speed", "loop", "yaw_deg"})) return *e;
    TrajectorySpec spec;
    const YAML::Node wps = node["waypoints"];
    if (!wps.IsDefined() || !wps.IsSequence() || wps.size() == 0) {
      return error(wps.IsDefined() ? wps : node, path + "waypoints", "expected a non-empty list of [x, y(, z)]");
    }
    for (std::size_t i = 0; i < wps.size(); ++i) {
      auto v = vectorNode(wps[i], path + "waypoints[" + std::to_string(i) + "]", 2, 3);
      if (!v) return Error::configuration(v.error().message);
      spec.waypoints.emplace_back((*v)[0], (*v)[1], (*v)[2]);
    }
    auto speed = number(node, "speed", path, 1.0);
    if (!speed) return Error::configuration(speed.error().message);
    if (!(*speed > 0.0)) return error(node["speed"], path + "speed", "must be positive");
    spec.speed = *speed;
    auto loop = boolean(node, "loop", path, false);
    if (!loop) return Error::configuration(loop.error().message);
    spec.loop = *loop;
    auto yaw = number(node, "yaw_deg", path, 0.0);
    if (!yaw) return Error::configuration(yaw.error().message);
    spec.yaw = *yaw * kRadiansPerDegree;
    return spec;
  }

  Result<std::size_t> materialIndex(const World& world, const YAML::Node& node, const std::string& path) const {
    auto name = string(node, "material", path, std::string("default"));
    if (!name) return Error::configuration(name.error().message);
    for (std::size_t i = 0; i < world.materials.size(); ++i) {
      if (world.materials[i].name == *name) return i;
    }
    return error(node["material"], path + "material", "no material named '" + *name + "'");
  }

  // `also`: further keys the caller reads (a moving solid's path and start_s).
  Result<Solid> solid(const World& world, const YAML::Node& node, const std::string& path,
                      std::initializer_list<const char*> also = {}) const {
    auto type = string(node, "type", path, std::nullopt);
    if (!type) return Error::configuration(type.error().message);
    auto material = materialIndex(world, node, path);
    if (!material) return Error::configuration(material.error().message);
    if (*type == "box") {
      if (auto e = onlyKeys(node, path, {"type", "center", "size", "yaw_deg", "material"}, also)) return *e;
      auto c = vector(node, "center", path, 3, 3);
      if (!c) return Error::configuration(c.error().message);
      auto s = vector(node, "size", path, 3, 3);
      if (!s) return Error::configuration(s.error().message);
      if ((s->array() <= 0.0).any()) return error(node["size"], path + "size", "every side must be positive");
      auto yaw = number(node, "yaw_deg", path, 0.0);
      if (!yaw) return Error::configuration(yaw.error().message);
      return Solid{Box{*c, *s, *yaw * kRadiansPerDegree}, *material};
    }
    if (*type == "cylinder") {
      if (auto e = onlyKeys(node, path, {"type", "center", "radius", "z", "material"}, also)) return *e;
      auto c = vector(node, "center", path, 2, 2);
      if (!c) return Error::configuration(c.error().message);
      auto r = number(node, "radius", path, std::nullopt);
      if (!r) return Error::configuration(r.error().message);
      if (!(*r > 0.0)) return error(node["radius"], path + "radius", "must be positive");
      auto z = vector(node, "z", path, 2, 2);
      if (!z) return Error::configuration(z.error().message);
      if (!((*z)[1] > (*z)[0])) return error(node["z"], path + "z", "expected [z_min, z_max] with z_max > z_min");
      return Solid{Cylinder{Eigen::Vector2d{(*c)[0], (*c)[1]}, *r, (*z)[0], (*z)[1]}, *material};
    }
    if (*type == "plane") {
      if (auto e = onlyKeys(node, path, {"type", "point", "normal", "material"}, also)) return *e;
      auto p = vector(node, "point", path, 3, 3);
      if (!p) return Error::configuration(p.error().message);
      auto n = vector(node, "normal", path, 3, 3);
      if (!n) return Error::configuration(n.error().message);
      if (n->norm() < 1e-9) return error(node["normal"], path + "normal", "must not be zero");
      const Eigen::Vector3d unit = Eigen::Vector3d(*n).normalized();
      return Solid{HalfSpace{unit, unit.dot(Eigen::Vector3d(*p))}, *material};
    }
    return error(node["type"], path + "type", "expected box, cylinder or plane, got '" + *type + "'");
  }

  Result<Scene> scene(const YAML::Node& root) const {
    if (auto e = onlyKeys(root, "", {"name", "bounds", "materials", "ground", "solids", "sensor_mount",
                                     "trajectories", "default_trajectory", "movers"})) {
      return *e;
    }
    Scene scene;
    World& world = scene.world;
    auto name = string(root, "name", "", std::string("unnamed"));
    if (!name) return Error::configuration(name.error().message);
    world.name = *name;
    world.materials.push_back(Material{"default", 50.0, 0.0});

    if (const YAML::Node mats = root["materials"]; mats.IsDefined()) {
      if (!mats.IsSequence()) return error(mats, "materials", "expected a list");
      for (std::size_t i = 0; i < mats.size(); ++i) {
        const std::string path = "materials[" + std::to_string(i) + "].";
        if (auto e = onlyKeys(mats[i], path, {"name", "reflectivity", "transmittance"})) return *e;
        auto mname = string(mats[i], "name", path, std::nullopt);
        if (!mname) return Error::configuration(mname.error().message);
        auto refl = number(mats[i], "reflectivity", path, 50.0);
        if (!refl) return Error::configuration(refl.error().message);
        if (*refl < 0.0 || *refl > 255.0) return error(mats[i]["reflectivity"], path + "reflectivity", "must be in 0..255");
        auto trans = number(mats[i], "transmittance", path, 0.0);
        if (!trans) return Error::configuration(trans.error().message);
        if (*trans < 0.0 || *trans >= 1.0) {
          return error(mats[i]["transmittance"], path + "transmittance", "must be in [0, 1)");
        }
        Material m{*mname, *refl, *trans};
        if (m.name == "default") {
          world.materials[0] = m;
        } else {
          world.materials.push_back(m);
        }
      }
    }

    if (const YAML::Node ground = root["ground"]; ground.IsDefined() && !ground.IsNull()) {
      if (auto e = onlyKeys(ground, "ground.", {"height", "material"})) return *e;
      auto h = number(ground, "height", "ground.", 0.0);
      if (!h) return Error::configuration(h.error().message);
      auto material = materialIndex(world, ground, "ground.");
      if (!material) return Error::configuration(material.error().message);
      world.solids.push_back(Solid{HalfSpace{Eigen::Vector3d::UnitZ(), *h}, *material});
    }

    if (const YAML::Node solids = root["solids"]; solids.IsDefined()) {
      if (!solids.IsSequence()) return error(solids, "solids", "expected a list");
      for (std::size_t i = 0; i < solids.size(); ++i) {
        auto s = solid(world, solids[i], "solids[" + std::to_string(i) + "].");
        if (!s) return Error::configuration(s.error().message);
        world.solids.push_back(*s);
      }
    }
    if (world.solids.empty()) return error(root, "solids", "the world has no ground and no solids");

    // Ground-truth region: as stated, or the finite solids' box padded by 1 m (down to one cell below a
    // ground).
    if (const YAML::Node bounds = root["bounds"]; bounds.IsDefined()) {
      if (auto e = onlyKeys(bounds, "bounds.", {"min", "max"})) return *e;
      auto lo = vector(bounds, "min", "bounds.", 3, 3);
      if (!lo) return Error::configuration(lo.error().message);
      auto hi = vector(bounds, "max", "bounds.", 3, 3);
      if (!hi) return Error::configuration(hi.error().message);
      if (!(hi->array() > lo->array()).all()) return error(bounds, "bounds", "max must exceed min on every axis");
      world.bounds = Aabb{*lo, *hi};
    } else {
      std::optional<Aabb> box;
      for (const auto& s : world.solids) {
        const auto b = boundsOf(s.shape);
        if (!b) continue;
        if (!box) box = *b;
        box->min = box->min.cwiseMin(b->min);
        box->max = box->max.cwiseMax(b->max);
      }
      if (!box) return error(root, "bounds", "required when the world has only planes");
      box->min.array() -= 1.0;
      box->max.array() += 1.0;
      world.bounds = *box;
    }

    if (const YAML::Node mount = root["sensor_mount"]; mount.IsDefined()) {
      if (auto e = onlyKeys(mount, "sensor_mount.", {"xyz", "rpy_deg"})) return *e;
      auto xyz = vector(mount, "xyz", "sensor_mount.", 3, 3);
      if (!xyz) return Error::configuration(xyz.error().message);
      Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
      if (mount["rpy_deg"].IsDefined()) {
        auto v = vector(mount, "rpy_deg", "sensor_mount.", 3, 3);
        if (!v) return Error::configuration(v.error().message);
        rpy = *v * kRadiansPerDegree;
      }
      scene.sensor_to_body = Eigen::Isometry3d::Identity();
      scene.sensor_to_body.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                                       Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                          .toRotationMatrix();
      scene.sensor_to_body.translation() = *xyz;
    } else {
      scene.sensor_to_body.translation() = Eigen::Vector3d{0.0, 0.0, 1.0};
    }

    if (const YAML::Node trajs = root["trajectories"]; trajs.IsDefined()) {
      if (!trajs.IsMap()) return error(trajs, "trajectories", "expected a mapping of name: trajectory");
      for (const auto& kv : trajs) {
        const std::string tname = kv.first.Scalar();
        auto t = trajectory(kv.second, "trajectories." + tname + ".");
        if (!t) return Error::configuration(t.error().message);
        scene.trajectories[tname] = *t;
      }
    }
    if (scene.trajectories.find("static") == scene.trajectories.end()) {
      // Every world offers "static": the middle of the ground-truth region, facing +x.
      const Eigen::Vector3d mid = 0.5 * (world.bounds.min + world.bounds.max);
      scene.trajectories["static"] = TrajectorySpec{{Eigen::Vector3d{mid.x(), mid.y(), 0.0}}, 1.0, false, 0.0};
    }
    auto def = string(root, "default_trajectory", "", std::string("static"));
    if (!def) return Error::configuration(def.error().message);
    if (scene.trajectories.find(*def) == scene.trajectories.end()) {
      return error(root["default_trajectory"], "default_trajectory", "no trajectory named '" + *def + "'");
    }
    scene.default_trajectory = *def;

    if (const YAML::Node movers = root["movers"]; movers.IsDefined()) {
      if (!movers.IsMap()) return error(movers, "movers", "expected a mapping of name: list of moving solids");
      for (const auto& kv : movers) {
        const std::string mname = kv.first.Scalar();
        if (!kv.second.IsSequence()) return error(kv.second, "movers." + mname, "expected a list");
        std::vector<MovingSolidSpec> set;
        for (std::size_t i = 0; i < kv.second.size(); ++i) {
          auto m = mover(world, kv.second[i], "movers." + mname + "[" + std::to_string(i) + "].");
          if (!m) return Error::configuration(m.error().message);
          set.push_back(*m);
        }
        scene.movers[mname] = std::move(set);
      }
    }
    return scene;
  }

  // A moving solid: the keys of a box or cylinder solid (in its own frame), plus path and start_s.
  Result<MovingSolidSpec> mover(const World& world, const YAML::Node& node, const std::string& path) const {
    if (!node.IsMap()) return error(node, path, "expected a mapping");
    auto s = solid(world, node, path, {"path", "start_s"});
    if (!s) return Error::configuration(s.error().message);
    if (std::holds_alternative<HalfSpace>(s->shape)) return error(node["type"], path + "type", "a moving solid is a box or a cylinder");
    const YAML::Node p = node["path"];
    if (!p.IsDefined()) return error(node, path + "path", "required: {speed, waypoints, loop}");
    auto t = trajectory(p, path + "path.");
    if (!t) return Error::configuration(t.error().message);
    auto start = number(node, "start_s", path, 0.0);
    if (!start) return Error::configuration(start.error().message);
    if (!(*start >= 0.0)) return error(node["start_s"], path + "start_s", "must be >= 0");
    return MovingSolidSpec{*s, *t, *start};
  }

 private:
  std::string source_;
};

Result<YAML::Node> loadYaml(std::string_view text, const std::string& source) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    return Error::configuration(source + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
}

Result<std::string> readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error::configuration(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Loads the YAML and hands the root to `parse`; a yaml-cpp exception on the way becomes an Error.
template <class T, class Parse>
Result<T> parseDocument(std::string_view yaml, const std::string& source, Parse parse) {
  auto root = loadYaml(yaml, source);
  if (!root) return Error::configuration(root.error().message);
  try {
    return parse(Parser(source), *root);
  } catch (const YAML::Exception& e) {
    return Error::configuration(source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

}  // namespace

Result<Scene> parseScene(std::string_view yaml, const std::string& source) {
  return parseDocument<Scene>(yaml, source, [](const Parser& p, const YAML::Node& root) { return p.scene(root); });
}

Result<Scene> loadSceneFile(const std::string& path) {
  auto text = readText(path);
  if (!text) return Error::configuration(text.error().message);
  return parseScene(*text, path);
}

Result<TrajectorySpec> parseTrajectory(std::string_view yaml, const std::string& source) {
  return parseDocument<TrajectorySpec>(
      yaml, source, [](const Parser& p, const YAML::Node& root) { return p.trajectory(root, ""); });
}

Result<TrajectorySpec> loadTrajectoryFile(const std::string& path) {
  auto text = readText(path);
  if (!text) return Error::configuration(text.error().message);
  return parseTrajectory(*text, path);
}

}  // namespace ogf::sim
