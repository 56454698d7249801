#include "ogf/map_io/map_config_file.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <string>

namespace ogf::map_io {
namespace {

std::string where(std::string_view source, const YAML::Node& node, std::string_view key) {
  return fmt::format("{}:{}: {}", source, node.Mark().line + 1, key);
}

template <class T>
Result<T> scalar(std::string_view source, const YAML::Node& node, std::string_view key) {
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    return Error{fmt::format("{}: '{}' is not a valid value", where(source, node, key),
                             node.IsScalar() ? node.Scalar() : std::string("<not a scalar>"))};
  }
}

Result<Eigen::VectorXd> vector(std::string_view source, const YAML::Node& node, std::string_view key,
                               Eigen::Index n) {
  if (!node.IsSequence() || static_cast<Eigen::Index>(node.size()) != n)
    return Error{fmt::format("{}: needs a list of {} numbers", where(source, node, key), n)};
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    auto x = scalar<double>(source, node[static_cast<std::size_t>(i)], key);
    if (!x) return x.error();
    v[i] = *x;
  }
  return v;
}

// Sets `target` from node; a helper so each key is one line below.
template <class T, class Target>
Status set(std::string_view source, const YAML::Node& node, std::string_view key, Target& target) {
  auto v = scalar<T>(source, node, key);
  if (!v) return v.error();
  target = *v;
  return okStatus();
}

Status applyExtrinsic(std::string_view source, const YAML::Node& map, fusion::ExtrinsicConfig& e) {
  if (!map.IsMap()) return Error{where(source, map, "extrinsic") + ": must be a mapping"};
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    const std::string path = "extrinsic." + key;
    if (key == "translation") {
      auto v = vector(source, kv.second, path, 3);
      if (!v) return v.error();
      e.translation_m = v->head<3>();
    } else if (key == "rpy") {
      auto v = vector(source, kv.second, path, 3);
      if (!v) return v.error();
      e.rpy_rad = v->head<3>();
    } else if (key == "quaternion") {
      auto v = vector(source, kv.second, path, 4);
      if (!v) return v.error();
      e.quaternion = Eigen::Quaterniond((*v)[0], (*v)[1], (*v)[2], (*v)[3]);
    } else {
      return Error{where(source, kv.first, path) + ": unknown key (translation, rpy, quaternion)"};
    }
  }
  return okStatus();
}

Status applyFilter(std::string_view source, const YAML::Node& map, filter::FilterConfig& f) {
  if (!map.IsMap()) return Error{where(source, map, "filter") + ": must be a mapping"};
  for (const auto& kv : map) {
    const std::string key = kv.first.Scalar();
    const std::string path = "filter." + key;
    const YAML::Node& v = kv.second;
    Status st = okStatus();
    if (key == "kernel_sigma") st = set<double>(source, v, path, f.kernelSigma);
    else if (key == "kernel_amplitude") st = set<double>(source, v, path, f.kernelAmplitude);
    else if (key == "stencil_radius") st = set<double>(source, v, path, f.stencilRadius);
    else if (key == "stencil_manhattan_radius") st = set<int>(source, v, path, f.stencilManhattanRadius);
    else if (key == "taper_support") st = set<double>(source, v, path, f.taperSupport);
    else if (key == "occupied_threshold") st = set<double>(source, v, path, f.occupiedThreshold);
    else if (key == "free_threshold") st = set<double>(source, v, path, f.freeThreshold);
    else if (key == "skip_tolerance") st = set<double>(source, v, path, f.skipTolerance);
    else if (key == "clamp_z") st = set<double>(source, v, path, f.clampZ);
    else if (key == "free_clamp_z") st = set<double>(source, v, path, f.freeClampZ);
    else if (key == "occupied_priority") {
      auto text = scalar<std::string>(source, v, path);
      if (!text) return text.error();
      const auto p = filter::parseOccupiedPriority(*text);
      if (!p) return Error{fmt::format("{}: 'scan' or 'map', got '{}'", where(source, v, path), *text)};
      f.occupiedPriority = *p;
    } else if (key == "covariance") {
      auto text = scalar<std::string>(source, v, path);
      if (!text) return text.error();
      const auto c = filter::parseCovarianceStorage(*text);
      if (!c) return Error{fmt::format("{}: 'compact' or 'banded', got '{}'", where(source, v, path), *text)};
      f.covariance = *c;
    } else if (key == "free_release_scans") st = set<int>(source, v, path, f.freeReleaseCount);
    else if (key == "threads") st = set<int>(source, v, path, f.threads);
    else
      return Error{where(source, kv.first, path) +
                   ": unknown key (kernel_sigma, kernel_amplitude, stencil_radius, stencil_manhattan_radius, "
                   "taper_support, occupied_threshold, free_threshold, skip_tolerance, clamp_z, free_clamp_z, "
                   "occupied_priority, free_release_scans, covariance, threads)"};
    if (!st) return st;
  }
  return okStatus();
}

}  // namespace

bool isMapperDaemonConfig(std::string_view yaml) {
  static constexpr std::string_view kDaemonOnly[] = {"map", "fusion", "channels", "lcm_url", "time_base",
                                                     "state_dir", "snapshot_interval_s", "keyframe_interval_s",
                                                     "status_interval_s", "pose_correction"};
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml));
  } catch (const YAML::Exception&) {
    return false;
  }
  if (!root.IsMap()) return false;
  for (const auto& kv : root) {
    if (!kv.first.IsScalar()) continue;
    for (const std::string_view key : kDaemonOnly) {
      if (kv.first.Scalar() == key) return true;
    }
  }
  return false;
}

Status applyMapConfigYaml(std::string_view yaml, std::string_view source, pipeline::MapperConfig& config) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml));
  } catch (const YAML::Exception& e) {
    return Error{fmt::format("{}:{}: {}", source, e.mark.line + 1, e.msg)};
  }
  if (root.IsNull()) return okStatus();  // an empty file changes nothing
  if (!root.IsMap()) return Error{fmt::format("{}: the top level must be a mapping of keys", source)};
  auto& m = config.fusion.measurement;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    const YAML::Node& v = kv.second;
    Status st = okStatus();
    if (key == "resolution") {
      auto r = scalar<double>(source, v, key);
      if (!r) return r.error();
      if (!(*r > 0)) return Error{where(source, v, key) + ": must be greater than 0, got " + v.Scalar()};
      config.setResolution(*r);
    } else if (key == "min_range") {
      st = set<double>(source, v, key, m.min_range_m);
      if (st && !(m.min_range_m >= 0)) return Error{where(source, v, key) + ": must be 0 or more, got " + v.Scalar()};
    } else if (key == "max_range") {
      st = set<double>(source, v, key, m.max_range_m);
      if (st && !(m.max_range_m > 0)) return Error{where(source, v, key) + ": must be greater than 0, got " + v.Scalar()};
    }
    else if (key == "free_space_for_no_return") st = set<bool>(source, v, key, m.free_space_for_no_return);
    else if (key == "extrinsic") st = applyExtrinsic(source, v, config.fusion.extrinsic);
    else if (key == "filter") st = applyFilter(source, v, config.filter);
    else
      return Error{where(source, kv.first, key) +
                   ": unknown key (resolution, min_range, max_range, free_space_for_no_return, extrinsic, filter)"};
    if (!st) return st;
  }
  return okStatus();
}

}  // namespace ogf::map_io
