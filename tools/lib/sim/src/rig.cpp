// Rig files (rig.hpp): read with yaml-cpp, every error naming the source, the line and the field.
#include "ogf/sim/rig.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "units.hpp"

namespace ogf::sim {
namespace {

constexpr const char* kFrontRear = R"(# Two VLP-16s: one low at the front looking ahead, one high at the back turned round and tilted down.
sensors:
  - {name: front, model: vlp16, rpm: 600, mount: {xyz: [0.5, 0.0, 0.4], rpy_deg: [0, 0, 0]}}
  - {name: rear, model: vlp16, rpm: 600, mount: {xyz: [-0.5, 0.0, 1.4], rpy_deg: [0, 15, 180]}}
)";

struct Reader {
  const std::string& source;

  Error error(const YAML::Node& at, const std::string& field, const std::string& what) const {
    return Error::configuration(source + ":" + std::to_string(at.Mark().line + 1) + ": " + field + ": " + what);
  }

  Result<Eigen::Vector3d> vector3(const YAML::Node& n, const std::string& field) const {
    if (!n.IsSequence() || n.size() != 3) return error(n, field, "expected 3 numbers");
    Eigen::Vector3d v;
    for (std::size_t i = 0; i < 3; ++i) {
      try {
        v[static_cast<Eigen::Index>(i)] = n[i].as<double>();
      } catch (const YAML::Exception&) {
        return error(n[i], field + "[" + std::to_string(i) + "]", "expected a number");
      }
      if (!std::isfinite(v[static_cast<Eigen::Index>(i)])) return error(n[i], field, "must be finite");
    }
    return v;
  }

  Result<Eigen::Isometry3d> mount(const YAML::Node& n, const std::string& field) const {
    if (!n.IsMap()) return error(n, field, "expected {xyz: [x, y, z], rpy_deg: [r, p, y]}");
    for (const auto& kv : n) {
      const std::string key = kv.first.as<std::string>();
      if (key != "xyz" && key != "rpy_deg") return error(kv.first, field + "." + key, "unknown key (xyz, rpy_deg)");
    }
    if (!n["xyz"]) return error(n, field + ".xyz", "missing");
    auto xyz = vector3(n["xyz"], field + ".xyz");
    if (!xyz) return xyz.error();
    Eigen::Vector3d rpy = Eigen::Vector3d::Zero();
    if (n["rpy_deg"]) {
      auto v = vector3(n["rpy_deg"], field + ".rpy_deg");
      if (!v) return v.error();
      rpy = *v * kRadiansPerDegree;
    }
    Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
    m.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    m.translation() = *xyz;
    return m;
  }

  Result<RigSensor> sensor(const YAML::Node& n, const std::string& field) const {
    if (!n.IsMap()) return error(n, field, "expected {name, model, rpm, mount}");
    RigSensor s;
    for (const auto& kv : n) {
      const std::string key = kv.first.as<std::string>();
      const std::string at = field + "." + key;
      if (key == "name") {
        s.name = kv.second.as<std::string>("");
      } else if (key == "model") {
        s.model = kv.second.as<std::string>("");
        if (*s.model != "vlp16" && *s.model != "hdl32e") return error(kv.second, at, "expected vlp16 or hdl32e");
      } else if (key == "rpm") {
        try {
          s.rpm = kv.second.as<double>();
        } catch (const YAML::Exception&) {
          return error(kv.second, at, "expected a number");
        }
        if (!(*s.rpm >= 300 && *s.rpm <= 1200)) return error(kv.second, at, "must be 300 to 1200");
      } else if (key == "mount") {
        auto m = mount(kv.second, at);
        if (!m) return m.error();
        s.sensor_to_body = *m;
      } else {
        return error(kv.first, at, "unknown key (name, model, rpm, mount)");
      }
    }
    const bool valid = !s.name.empty() && s.name.size() <= 32 && std::all_of(s.name.begin(), s.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
    });
    if (!valid) return error(n, field + ".name", "must be 1 to 32 letters, digits, '_' or '-'");
    if (!n["mount"]) return error(n, field + ".mount", "missing");
    return s;
  }
};

}  // namespace

Result<Rig> parseRig(std::string_view yaml, const std::string& source) {
  try {
    const YAML::Node root = YAML::Load(std::string(yaml));
    const Reader r{source};
    if (!root.IsMap() || !root["sensors"]) return r.error(root, "sensors", "missing: a rig lists its sensors");
    for (const auto& kv : root)
      if (kv.first.as<std::string>() != "sensors") return r.error(kv.first, kv.first.as<std::string>(), "unknown key (sensors)");
    const YAML::Node list = root["sensors"];
    if (!list.IsSequence() || list.size() == 0) return r.error(list, "sensors", "expected a list of at least one sensor");
    Rig rig;
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string field = "sensors[" + std::to_string(i) + "]";
      auto s = r.sensor(list[i], field);
      if (!s) return s.error();
      if (!names.insert(s->name).second) return r.error(list[i], field + ".name", "'" + s->name + "' is used twice");
      rig.sensors.push_back(std::move(*s));
    }
    return rig;
  } catch (const YAML::Exception& e) {
    return Error::configuration(source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

std::vector<std::string> rigPresetNames() { return {"front-rear"}; }

Result<Rig> resolveRig(const std::string& preset_or_path) {
  if (preset_or_path == "front-rear") return parseRig(kFrontRear, "front-rear");
  std::ifstream in(preset_or_path);
  if (!in) return Error::io(preset_or_path + ": cannot read the rig file (built-in rigs: front-rear)");
  std::ostringstream text;
  text << in.rdbuf();
  return parseRig(text.str(), preset_or_path);
}

}  // namespace ogf::sim
