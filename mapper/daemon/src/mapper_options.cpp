#include "ogf/mapper_daemon/mapper_options.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace ogf::mapper_daemon {
namespace {

std::string where(const std::filesystem::path& path, const YAML::Node& node, const std::string& key) {
  return path.string() + ":" + std::to_string(node.Mark().line + 1) + ": " + key;
}

// Refuses keys this section does not know.
Status checkKeys(const std::filesystem::path& path, const YAML::Node& node, const std::string& section,
                 const std::set<std::string>& known) {
  if (!node.IsMap()) return Error{where(path, node, section) + ": expected a mapping"};
  for (const auto& kv : node) {
    const auto key = kv.first.as<std::string>();
    if (known.count(key) == 0)
      return Error{where(path, kv.first, section.empty() ? key : section + "." + key) + ": unknown key"};
  }
  return okStatus();
}

template <class T>
Status read(const std::filesystem::path& path, const YAML::Node& parent, const std::string& section,
            const char* key, T& out) {
  const YAML::Node n = parent[key];
  if (!n) return okStatus();
  try {
    out = n.as<T>();
  } catch (const YAML::Exception&) {
    return Error{where(path, n, section.empty() ? key : section + "." + key) + ": cannot read '" + n.Scalar() + "'"};
  }
  return okStatus();
}

template <class T>
Status readOptional(const std::filesystem::path& path, const YAML::Node& parent, const std::string& section,
                    const char* key, std::optional<T>& out) {
  if (!parent[key]) return okStatus();
  T v{};
  if (auto st = read(path, parent, section, key, v); !st) return st;
  out = v;
  return okStatus();
}

// A number the map cannot do without: > 0 (or >= 0 with `zero_ok`), reported at the value's line with
// the key as written.
Status requireRange(const std::filesystem::path& path, const YAML::Node& parent, const std::string& section,
                    const char* key, double value, bool zero_ok) {
  const YAML::Node n = parent[key];
  if (!n || value > 0 || (zero_ok && value == 0)) return okStatus();
  return Error{where(path, n, section + "." + key) + ": must be " + (zero_ok ? "0 or more" : "greater than 0") +
               ", got " + n.Scalar()};
}

Status readVector3(const std::filesystem::path& path, const YAML::Node& parent, const std::string& section,
                   const char* key, Eigen::Vector3d& out) {
  const YAML::Node n = parent[key];
  if (!n) return okStatus();
  if (!n.IsSequence() || n.size() != 3) return Error{where(path, n, section + "." + key) + ": expected [x, y, z]"};
  for (std::size_t i = 0; i < 3; ++i) {
    try {
      out[static_cast<Eigen::Index>(i)] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      return Error{where(path, n[i], section + "." + key) + ": cannot read '" + n[i].Scalar() + "'"};
    }
  }
  return okStatus();
}

// A rigid transform as {translation: [x, y, z], rpy: [roll, pitch, yaw]} or with quaternion: [w, x, y, z].
Status readTransform(const std::filesystem::path& path, const YAML::Node& node, const std::string& section,
                     fusion::ExtrinsicConfig& out) {
  if (auto st = checkKeys(path, node, section, {"translation", "rpy", "quaternion"}); !st) return st;
  if (auto st = readVector3(path, node, section, "translation", out.translation_m); !st) return st;
  if (auto st = readVector3(path, node, section, "rpy", out.rpy_rad); !st) return st;
  if (const auto q = node["quaternion"]) {
    if (!q.IsSequence() || q.size() != 4) return Error{where(path, q, section + ".quaternion") + ": expected [w, x, y, z]"};
    out.quaternion = Eigen::Quaterniond(q[0].as<double>(), q[1].as<double>(), q[2].as<double>(), q[3].as<double>());
  }
  return okStatus();
}

Status parseMapperYaml(const YAML::Node& root, const std::filesystem::path& path, MapperOptions& o);

#define OGF_TRY(expr)                  \
  if (auto st_ = (expr); !st_) return st_

}  // namespace

Status MapperOptions::validate() const {
  if (auto st = map.validate(); !st) return Error{"map: " + st.error().message};
  if (auto st = pose_correction.validate(); !st) return Error{"pose_correction: " + st.error().message};
  if (auto st = static_pose.validate(); !st) return Error{"static_pose: " + st.error().message};
  if (pose_source == PoseSource::kStatic && pose_correction.corrector.mode != slam::CorrectionMode::kNone)
    return Error{"pose_correction: must be none with pose_source static (a fixed pose has no odometry to correct)"};
  for (const auto* ch : {&scan_channel, &pose_channel, &delta_channel, &request_channel, &status_channel,
                         &corrected_pose_channel, &query_channel, &command_channel}) {
    if (ch->empty() || ch->size() > 63) return Error{"channels: '" + *ch + "' must be 1 to 63 characters"};
  }
  for (const auto* ch : {&query_channel, &command_channel}) {
    if (ch->size() > 57) return Error{"channels: '" + *ch + "' must be 1 to 57 characters (its reply adds _REPLY)"};
  }
  if (!(snapshot_interval_s > 0)) return Error{"snapshot_interval_s: must be > 0"};
  if (!(page_out_distance_m >= 0) || !std::isfinite(page_out_distance_m))
    return Error{"page_out_distance_m: must be >= 0 (0 keeps the whole map in memory)"};
  if (!(keyframe_interval_s > 0)) return Error{"keyframe_interval_s: must be > 0"};
  if (!(status_interval_s > 0)) return Error{"status_interval_s: must be > 0"};
  if (!(test_drop_delta_fraction >= 0 && test_drop_delta_fraction < 1))
    return Error{"test_drop_delta_fraction: must be in [0, 1)"};
  return okStatus();
}

Status loadMapperOptions(const std::filesystem::path& path, MapperOptions& o) {
  std::ifstream in(path);
  if (!in) return Error{path.string() + ": cannot read the file"};
  std::ostringstream text;
  text << in.rdbuf();  // an empty file gives "", an empty configuration
  return parseMapperOptions(text.str(), path, o);
}

Status parseMapperOptions(const std::string& yaml, const std::filesystem::path& path, MapperOptions& o) {
  // Any YAML exception the reading below does not catch itself (a key that is not a scalar, a value of the
  // wrong kind) is still an error in this file, never an exception out of the program's start-up.
  try {
    return parseMapperYaml(YAML::Load(yaml), path, o);
  } catch (const YAML::Exception& e) {
    return Error{path.string() + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg};
  }
}

namespace {

Status parseMapperYaml(const YAML::Node& root, const std::filesystem::path& path, MapperOptions& o) {
  if (!root || root.IsNull()) return okStatus();
  OGF_TRY(checkKeys(path, root, "", {"lcm_url", "channels", "time_base", "pose_source", "static_pose", "state_dir",
                                     "snapshot_interval_s", "page_out_distance_m",
                                     "keyframe_interval_s", "status_interval_s", "map", "filter", "fusion",
                                     "pose_correction"}));
  OGF_TRY(read(path, root, "", "lcm_url", o.lcm_url));
  std::string state_dir = o.state_dir.string();
  OGF_TRY(read(path, root, "", "state_dir", state_dir));
  o.state_dir = state_dir;
  OGF_TRY(read(path, root, "", "snapshot_interval_s", o.snapshot_interval_s));
  OGF_TRY(read(path, root, "", "page_out_distance_m", o.page_out_distance_m));
  OGF_TRY(read(path, root, "", "keyframe_interval_s", o.keyframe_interval_s));
  OGF_TRY(read(path, root, "", "status_interval_s", o.status_interval_s));
  if (const auto tb = root["time_base"]) {
    const auto v = tb.as<std::string>();
    if (v == "device") o.time_base = ScanTimeBase::kDevice;
    else if (v == "host") o.time_base = ScanTimeBase::kHost;
    else if (v == "auto") o.time_base = ScanTimeBase::kAuto;
    else return Error{where(path, tb, "time_base") + ": 'auto', 'device' or 'host', got '" + v + "'"};
  }
  if (const auto ps = root["pose_source"]) {
    const auto v = ps.as<std::string>();
    if (v == "odometry") o.pose_source = MapperOptions::PoseSource::kOdometry;
    else if (v == "static") o.pose_source = MapperOptions::PoseSource::kStatic;
    else return Error{where(path, ps, "pose_source") + ": 'odometry' or 'static', got '" + v + "'"};
  }
  if (const auto sp = root["static_pose"]) OGF_TRY(readTransform(path, sp, "static_pose", o.static_pose));
  if (const auto ch = root["channels"]) {
    OGF_TRY(checkKeys(path, ch, "channels",
                      {"scan", "pose", "delta", "request", "status", "corrected_pose", "query", "command"}));
    OGF_TRY(read(path, ch, "channels", "scan", o.scan_channel));
    OGF_TRY(read(path, ch, "channels", "pose", o.pose_channel));
    OGF_TRY(read(path, ch, "channels", "delta", o.delta_channel));
    OGF_TRY(read(path, ch, "channels", "request", o.request_channel));
    OGF_TRY(read(path, ch, "channels", "status", o.status_channel));
    OGF_TRY(read(path, ch, "channels", "corrected_pose", o.corrected_pose_channel));
    OGF_TRY(read(path, ch, "channels", "query", o.query_channel));
    OGF_TRY(read(path, ch, "channels", "command", o.command_channel));
  }
  if (const auto pc = root["pose_correction"]) {
    OGF_TRY(checkKeys(path, pc, "pose_correction", {"mode", "particles", "band_z_min", "band_z_max", "seed"}));
    if (const auto mode = pc["mode"]) {
      const auto parsed = slam::parseCorrectionMode(mode.as<std::string>());
      if (!parsed) return Error{where(path, mode, "pose_correction.mode") + ": " + parsed.error().message};
      o.pose_correction.corrector.mode = *parsed;
    }
    auto& slam_config = o.pose_correction.corrector.slam;
    OGF_TRY(read(path, pc, "pose_correction", "particles", slam_config.particles));
    OGF_TRY(read(path, pc, "pose_correction", "seed", slam_config.seed));
    OGF_TRY(read(path, pc, "pose_correction", "band_z_min", o.pose_correction.projection.z_min_m));
    OGF_TRY(read(path, pc, "pose_correction", "band_z_max", o.pose_correction.projection.z_max_m));
  }
  auto& m = o.map.fusion.measurement;
  if (const auto map = root["map"]) {
    OGF_TRY(checkKeys(path, map, "map", {"resolution", "min_range", "max_range", "free_space_for_no_return", "extrinsic"}));
    double res = m.resolution_m;
    OGF_TRY(read(path, map, "map", "resolution", res));
    OGF_TRY(requireRange(path, map, "map", "resolution", res, false));
    o.map.setResolution(res);
    OGF_TRY(read(path, map, "map", "min_range", m.min_range_m));
    OGF_TRY(requireRange(path, map, "map", "min_range", m.min_range_m, true));
    OGF_TRY(read(path, map, "map", "max_range", m.max_range_m));
    OGF_TRY(requireRange(path, map, "map", "max_range", m.max_range_m, false));
    OGF_TRY(read(path, map, "map", "free_space_for_no_return", m.free_space_for_no_return));
    if (const auto ex = map["extrinsic"]) OGF_TRY(readTransform(path, ex, "map.extrinsic", o.map.fusion.extrinsic));
  }
  if (const auto f = root["filter"]) {
    auto& fc = o.map.filter;
    OGF_TRY(checkKeys(path, f, "filter", {"sigma", "amplitude", "stencil_radius", "taper_support", "occupied_threshold",
                                          "free_threshold", "skip_tolerance", "clamp_z", "free_clamp_z",
                                          "occupied_priority", "free_release_scans", "covariance", "threads"}));
    OGF_TRY(readOptional(path, f, "filter", "sigma", fc.kernelSigma));
    OGF_TRY(readOptional(path, f, "filter", "amplitude", fc.kernelAmplitude));
    OGF_TRY(readOptional(path, f, "filter", "stencil_radius", fc.stencilRadius));
    OGF_TRY(readOptional(path, f, "filter", "taper_support", fc.taperSupport));
    OGF_TRY(read(path, f, "filter", "occupied_threshold", fc.occupiedThreshold));
    OGF_TRY(read(path, f, "filter", "free_threshold", fc.freeThreshold));
    OGF_TRY(read(path, f, "filter", "skip_tolerance", fc.skipTolerance));
    OGF_TRY(read(path, f, "filter", "clamp_z", fc.clampZ));
    OGF_TRY(read(path, f, "filter", "free_clamp_z", fc.freeClampZ));
    if (const auto op = f["occupied_priority"]) {
      const std::string v = op.as<std::string>("");
      const auto p = filter::parseOccupiedPriority(v);
      if (!p) return Error{where(path, op, "filter.occupied_priority") + ": 'scan' or 'map', got '" + v + "'"};
      fc.occupiedPriority = *p;
    }
    OGF_TRY(read(path, f, "filter", "free_release_scans", fc.freeReleaseCount));
    if (const auto cv = f["covariance"]) {
      const std::string v = cv.as<std::string>("");
      const auto c = filter::parseCovarianceStorage(v);
      if (!c) return Error{where(path, cv, "filter.covariance") + ": 'compact' or 'banded', got '" + v + "'"};
      fc.covariance = *c;
    }
    OGF_TRY(read(path, f, "filter", "threads", fc.threads));
  }
  if (const auto fu = root["fusion"]) {
    auto& fc = o.map.fusion;
    OGF_TRY(checkKeys(path, fu, "fusion", {"max_pose_wait_s", "pose_buffer_capacity", "max_pending_scans",
                                           "max_pending_points", "max_pose_jump", "quaternion_tolerance",
                                           "max_time_ahead_s", "max_time_behind_s", "clock_jump_messages"}));
    OGF_TRY(read(path, fu, "fusion", "max_pose_wait_s", fc.pending.max_pose_wait_s));
    OGF_TRY(read(path, fu, "fusion", "pose_buffer_capacity", fc.pose_buffer.capacity));
    OGF_TRY(read(path, fu, "fusion", "max_pending_scans", fc.pending.max_pending_scans));
    OGF_TRY(read(path, fu, "fusion", "max_pending_points", fc.pending.max_pending_points));
    if (const auto jump = fu["max_pose_jump"]) {
      OGF_TRY(checkKeys(path, jump, "fusion.max_pose_jump", {"translation_m", "rotation_rad"}));
      OGF_TRY(read(path, jump, "fusion.max_pose_jump", "translation_m", fc.pose_buffer.jump_translation_m));
      OGF_TRY(read(path, jump, "fusion.max_pose_jump", "rotation_rad", fc.pose_buffer.jump_rotation_rad));
    }
    OGF_TRY(read(path, fu, "fusion", "max_time_ahead_s", fc.time_sanity.max_ahead_s));
    OGF_TRY(read(path, fu, "fusion", "max_time_behind_s", fc.time_sanity.max_behind_s));
    OGF_TRY(read(path, fu, "fusion", "clock_jump_messages", fc.time_sanity.follow_after));
    OGF_TRY(read(path, fu, "fusion", "quaternion_tolerance", fc.pose_buffer.quaternion_tolerance));
  }
  return okStatus();
}

}  // namespace

std::string exampleMapperConfig() {
  const MapperOptions d;
  const auto& m = d.map.fusion.measurement;
  std::ostringstream s;
  s << "# ogf-mapper configuration (YAML). Every key is optional; shown with its default.\n"
    << "lcm_url: \"\"                # empty: $LCM_DEFAULT_URL, else udpm://239.255.76.67:7667?ttl=0\n"
    << "channels: {scan: " << d.scan_channel << ", pose: " << d.pose_channel << ", delta: " << d.delta_channel
    << ", request: " << d.request_channel << ", status: " << d.status_channel
    << ", corrected_pose: " << d.corrected_pose_channel << ",\n"
    << "           query: " << d.query_channel << ", command: " << d.command_channel
    << "}   # map services answer on <channel>_REPLY\n"
    << "time_base: auto            # the scan clock odometry utime shares: device, host, or auto (device when\n"
    << "                           # the driver reports PPS locked, host otherwise)\n"
    << "pose_source: odometry      # odometry (the pose channel), or static: every scan at static_pose, no odometry\n"
    << "static_pose: {translation: [0, 0, 0], rpy: [0, 0, 0]}   # body -> map with pose_source static; or quaternion\n"
    << "state_dir: \"\"              # snapshots + journal; empty keeps the map in memory only\n"
    << "snapshot_interval_s: " << d.snapshot_interval_s << "\n"
    << "page_out_distance_m: " << d.page_out_distance_m
    << "   # farther map regions wait in <state_dir>/pages; 0 keeps the whole map in memory\n"
    << "keyframe_interval_s: " << d.keyframe_interval_s << "\n"
    << "status_interval_s: " << d.status_interval_s << "\n"
    << "map:\n"
    << "  resolution: " << m.resolution_m << "          # metres per cell\n"
    << "  min_range: " << m.min_range_m << "\n"
    << "  max_range: " << m.max_range_m << "\n"
    << "  free_space_for_no_return: false\n"
    << "  extrinsic: {translation: [0, 0, 0], rpy: [0, 0, 0]}   # sensor -> body; or quaternion: [w, x, y, z]\n"
    << "filter:                     # Sun et al. Sec. VI defaults\n"
    << "  # sigma: resolution/2, amplitude: 1/(sigma*sqrt(2*pi)), stencil_radius and taper_support derived\n"
    << "  occupied_threshold: 0.65\n"
    << "  free_threshold: 0.35\n"
    << "  skip_tolerance: 1e-4\n"
    << "  clamp_z: 3                # skip a measurement agreeing with its cell beyond this probit z; 0: never\n"
    << "  free_clamp_z: 1.5         # the same for free measurements (most of a scan); 0: clamp_z\n"
    << "  occupied_priority: " << filter::toString(d.map.filter.occupiedPriority)
    << "      # map: a cell once measured occupied ignores free measurements (scan: exact filter)\n"
    << "  free_release_scans: " << d.map.filter.freeReleaseCount
    << "    # ... until this many scans in a row measure it free; 0: never\n"
    << "  covariance: " << filter::toString(d.map.filter.covariance)
    << "       # compact: mean and variance per cell; banded: also the covariances (exact, 6x the memory)\n"
    << "  threads: 1\n"
    << "fusion:\n"
    << "  max_pose_wait_s: " << d.map.fusion.pending.max_pose_wait_s << "\n"
    << "  pose_buffer_capacity: " << d.map.fusion.pose_buffer.capacity << "\n"
    << "  max_pending_scans: " << d.map.fusion.pending.max_pending_scans << "\n"
    << "  max_pending_points: " << d.map.fusion.pending.max_pending_points << "\n"
    << "  max_pose_jump: {translation_m: " << d.map.fusion.pose_buffer.jump_translation_m
    << ", rotation_rad: " << d.map.fusion.pose_buffer.jump_rotation_rad
    << "}   # a larger odometry step splits the trajectory\n"
    << "  max_time_ahead_s: " << d.map.fusion.time_sanity.max_ahead_s
    << "      # a pose or scan this far ahead of the host clock or its stream is refused\n"
    << "  max_time_behind_s: " << d.map.fusion.time_sanity.max_behind_s << "     # ... or this far behind its stream\n"
    << "  clock_jump_messages: " << d.map.fusion.time_sanity.follow_after
    << "    # refused messages in a row that agree: the clock really jumped, follow it\n"
    << "pose_correction:            # between odometry and the map; corrected poses on channels.corrected_pose\n"
    << "  mode: none                # none, scan-match (improved odometry) or rbpf (grid-based FastSLAM)\n"
    << "  particles: " << d.pose_correction.corrector.slam.particles << "             # rbpf only\n"
    << "  band_z_min: " << d.pose_correction.projection.z_min_m
    << "           # body-frame height band cut into the planar scan, metres\n"
    << "  band_z_max: " << d.pose_correction.projection.z_max_m << "\n"
    << "  seed: " << d.pose_correction.corrector.slam.seed << "\n";
  return s.str();
}

}  // namespace ogf::mapper_daemon
