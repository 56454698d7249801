// Every configuration key of the mapping programs, declared once: path, type, default (the value a
// default-constructed MapperOptions holds), unit, meaning, the programs that use it, its check and where it
// lands in MapperOptions. mapper_options.cpp makes the YAML reader, --print-config and the README's table
// from this list.
#include "config_schema.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace ogf::mapper_daemon::schema {

std::string yamlNumber(double value) {
  std::array<char, 64> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), value);
  if (ec != std::errc{}) return "0";
  return std::string(buf.data(), end);
}

std::string yamlText(const std::string& text) {
  const bool plain = !text.empty() && text.front() != '-' && text != "null" && text != "Null" && text != "NULL" &&
                     std::all_of(text.begin(), text.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '.' || c == '/' ||
                              c == '-' || c == '+' || c == '=';
                     });
  if (plain) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      constexpr char kHex[] = "0123456789abcdef";
      quoted += "\\x";
      quoted += kHex[(c >> 4) & 0xf];
      quoted += kHex[c & 0xf];
    } else {
      quoted += c;
    }
  }
  return quoted + "\"";
}

namespace {

Status readVector(const YAML::Node& n, const Locate& where, std::string_view subkey, std::size_t size, double* out) {
  const char* form = size == 3 ? "expected [x, y, z]" : "expected [w, x, y, z]";
  if (!n.IsSequence() || n.size() != size) return Error::configuration(where(n, subkey) + ": " + form);
  for (std::size_t i = 0; i < size; ++i) {
    if (!n[i].IsScalar()) return Error::configuration(where(n[i], subkey) + ": " + form);
    try {
      out[i] = n[i].as<double>();
    } catch (const YAML::Exception&) {
      return Error::configuration(where(n[i], subkey) + ": cannot read '" + n[i].Scalar() + "' as a number");
    }
    if (!std::isfinite(out[i])) return Error::configuration(where(n[i], subkey) + ": must be finite, got " + n[i].Scalar());
  }
  return okStatus();
}

std::string yamlVector(std::initializer_list<double> values) {
  std::string s = "[";
  for (const double v : values) s += (s.size() > 1 ? ", " : "") + yamlNumber(v);
  return s + "]";
}

}  // namespace

Status readPose(const YAML::Node& n, const Locate& where, std::string_view prefix, fusion::ExtrinsicConfig& pose) {
  const auto sub = [&](const std::string& name) { return prefix.empty() ? name : std::string(prefix) + "." + name; };
  if (!n.IsMap())
    return Error::configuration(where(n, prefix) + ": expected {translation: [x, y, z], rpy: [r, p, y]}");
  for (const auto& kv : n) {
    const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
    if (name == "translation") {
      if (auto st = readVector(kv.second, where, sub(name), 3, pose.translation_m.data()); !st) return st;
    } else if (name == "rpy") {
      if (auto st = readVector(kv.second, where, sub(name), 3, pose.rpy_rad.data()); !st) return st;
    } else if (name == "quaternion") {
      double q[4];
      if (auto st = readVector(kv.second, where, sub(name), 4, q); !st) return st;
      pose.quaternion = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    } else {
      return Error::configuration(where(kv.first, sub(name)) + ": unknown key (translation, rpy, quaternion)");
    }
  }
  return okStatus();
}

std::string showPose(const fusion::ExtrinsicConfig& pose) {
  const Eigen::Vector3d& t = pose.translation_m;
  std::string s = "{translation: " + yamlVector({t.x(), t.y(), t.z()});
  if (pose.quaternion) {
    const Eigen::Quaterniond& q = *pose.quaternion;
    s += ", quaternion: " + yamlVector({q.w(), q.x(), q.y(), q.z()});
  } else {
    s += ", rpy: " + yamlVector({pose.rpy_rad.x(), pose.rpy_rad.y(), pose.rpy_rad.z()});
  }
  return s + "}";
}

namespace {

constexpr unsigned kMapper = kUsedByMapper;
constexpr unsigned kOffline = kUsedByMapper | kUsedByMap;  // the programs that map from odometry or a pose
constexpr unsigned kAll = kUsedByMapper | kUsedByMap | kUsedByEval;

// Why a number is refused ("must be greater than 0"), or nothing.
using NumberCheck = std::optional<std::string> (*)(double);

std::optional<std::string> anyNumber(double) { return std::nullopt; }
std::optional<std::string> positive(double v) {
  return v > 0 ? std::nullopt : std::optional<std::string>("must be greater than 0");
}
std::optional<std::string> nonNegative(double v) {
  return v >= 0 ? std::nullopt : std::optional<std::string>("must be 0 or more");
}
std::optional<std::string> probability(double v) {
  return v > 0 && v < 1 ? std::nullopt : std::optional<std::string>("must be between 0 and 1 (exclusive)");
}

Result<double> readNumber(const YAML::Node& n, const Locate& where) {
  if (!n.IsScalar()) return Error::configuration(where(n, "") + ": expected a number");
  double v = 0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    return Error::configuration(where(n, "") + ": cannot read '" + n.Scalar() + "' as a number");
  }
  if (!std::isfinite(v)) return Error::configuration(where(n, "") + ": must be a finite number, got " + n.Scalar());
  return v;
}

Result<long long> readInteger(const YAML::Node& n, const Locate& where, long long lo, long long hi) {
  if (!n.IsScalar()) return Error::configuration(where(n, "") + ": expected an integer");
  long long v = 0;
  try {
    v = n.as<long long>();
  } catch (const YAML::Exception&) {
    return Error::configuration(where(n, "") + ": cannot read '" + n.Scalar() + "' as an integer");
  }
  if (v < lo || v > hi)
    return Error::configuration(where(n, "") + ": must be from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " +
                 n.Scalar());
  return v;
}

Result<std::string> readText(const YAML::Node& n, const Locate& where) {
  if (!n.IsScalar()) return Error::configuration(where(n, "") + ": expected text");
  return n.Scalar();
}

// A number in MapperOptions; `at` is a generic lambda returning the field of a (const) MapperOptions.
template <class Access>
ConfigKey numberKey(std::string path, std::string unit, std::string meaning, unsigned users, NumberCheck check,
                    Access at) {
  return {std::move(path), "number", std::move(unit), std::move(meaning), users,
          [at, check](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            auto v = readNumber(n, where);
            if (!v) return v.error();
            if (auto why = check(*v)) return Error::configuration(where(n, "") + ": " + *why + ", got " + n.Scalar());
            at(o) = *v;
            return okStatus();
          },
          [at](const MapperOptions& o) { return yamlNumber(at(o)); }, ""};
}

// A number whose default is derived from other keys (std::optional, empty = derived): `auto` says so.
template <class Access>
ConfigKey derivedNumberKey(std::string path, std::string unit, std::string meaning, unsigned users, std::string note,
                           Access at) {
  return {std::move(path), "number or `auto`", std::move(unit), std::move(meaning), users,
          [at](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            if (n.IsScalar() && n.Scalar() == "auto") {
              at(o).reset();
              return okStatus();
            }
            auto v = readNumber(n, where);
            if (!v) return v.error();
            if (auto why = positive(*v)) return Error::configuration(where(n, "") + ": " + *why + " (or auto), got " + n.Scalar());
            at(o) = *v;
            return okStatus();
          },
          [at](const MapperOptions& o) { return at(o) ? yamlNumber(*at(o)) : std::string("auto"); },
          "`auto`: " + std::move(note)};
}

template <class Access>
ConfigKey integerKey(std::string path, std::string unit, std::string meaning, unsigned users, long long lo,
                     long long hi, Access at) {
  return {std::move(path), "integer", std::move(unit), std::move(meaning), users,
          [at, lo, hi](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            auto v = readInteger(n, where, lo, hi);
            if (!v) return v.error();
            at(o) = static_cast<std::remove_reference_t<decltype(at(o))>>(*v);
            return okStatus();
          },
          [at](const MapperOptions& o) { return std::to_string(at(o)); }, ""};
}

template <class Access>
ConfigKey boolKey(std::string path, std::string meaning, unsigned users, Access at) {
  return {std::move(path), "`true` or `false`", "", std::move(meaning), users,
          [at](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            if (!n.IsScalar()) return Error::configuration(where(n, "") + ": expected true or false");
            try {
              at(o) = n.as<bool>();
            } catch (const YAML::Exception&) {
              return Error::configuration(where(n, "") + ": expected true or false, got '" + n.Scalar() + "'");
            }
            return okStatus();
          },
          [at](const MapperOptions& o) { return std::string(at(o) ? "true" : "false"); }, ""};
}

// A text; `max_length` 0 = any length, else 1 to max_length characters.
template <class Access>
ConfigKey textKey(std::string path, std::string meaning, unsigned users, std::size_t max_length, Access at,
                  std::string note = "") {
  return {std::move(path), "text", "", std::move(meaning), users,
          [at, max_length](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            auto v = readText(n, where);
            if (!v) return v.error();
            if (max_length > 0 && (v->empty() || v->size() > max_length))
              return Error::configuration(where(n, "") + ": must be 1 to " + std::to_string(max_length) + " characters, got '" + *v +
                           "'");
            at(o) = *v;
            return okStatus();
          },
          [at](const MapperOptions& o) { return yamlText(at(o)); },
          std::move(note)};
}

// One of a few names, each standing for a value of an enum.
template <class Enum, class Access>
ConfigKey choiceKey(std::string path, std::string meaning, unsigned users,
                    std::vector<std::pair<std::string, Enum>> names, Access at) {
  std::string type;
  for (std::size_t i = 0; i < names.size(); ++i)
    type += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + ("`" + names[i].first + "`");
  std::string listed;
  for (std::size_t i = 0; i < names.size(); ++i) listed += (i == 0 ? "'" : ", '") + names[i].first + "'";
  return {std::move(path), type, "", std::move(meaning), users,
          [at, names, listed](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            if (!n.IsScalar()) return Error::configuration(where(n, "") + ": expected one of " + listed);
            for (const auto& [name, value] : names) {
              if (n.Scalar() == name) {
                at(o) = value;
                return okStatus();
              }
            }
            return Error::configuration(where(n, "") + ": expected one of " + listed + ", got '" + n.Scalar() + "'");
          },
          [at, names](const MapperOptions& o) {
            for (const auto& [name, value] : names)
              if (at(o) == value) return name;
            return std::string("?");
          },
          ""};
}

// A rigid transform: {translation: [x, y, z], rpy: [roll, pitch, yaw]} or {translation, quaternion: [w, x,
// y, z]} (the quaternion replaces rpy). Sub-keys not given keep their values.
template <class Access>
ConfigKey poseKey(std::string path, std::string meaning, unsigned users, Access at) {
  return {std::move(path), "{translation, rpy or quaternion}", "m, rad", std::move(meaning), users,
          [at](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            return readPose(n, where, "", at(o));
          },
          [at](const MapperOptions& o) { return showPose(at(o)); }, ""};
}

// A channel name: LCM allows 63 characters; a service's reply adds "_REPLY", leaving it 57.
constexpr std::size_t kChannelLength = 63;
constexpr std::size_t kServiceChannelLength = kChannelLength - 6;

// A file's path in the services section: any text ("" = none).
ConfigKey servicesPathKey(std::string path, std::string meaning, std::filesystem::path ServicesOptions::*in_services,
                          std::string note) {
  return {std::move(path), "text", "", std::move(meaning), kMapper,
          [in_services](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            auto v = readText(n, where);
            if (!v) return v.error();
            o.services.*in_services = *v;
            return okStatus();
          },
          [in_services](const MapperOptions& o) { return yamlText((o.services.*in_services).string()); },
          std::move(note)};
}

// The LCM bus and the channels the mapper listens and speaks on.
void declareBus(std::vector<ConfigKey>& k) {
  k.push_back(textKey("lcm_url", "the LCM bus; empty: `$LCM_DEFAULT_URL`, else `udpm://239.255.76.67:7667?ttl=0`",
                      kMapper, 0, [](auto& o) -> auto& { return o.lcm_url; }));
  k.push_back(textKey("channels.scan", "scans in (`ogf.lidar_scan_t`)", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.scan_channel; }));
  k.push_back(textKey("channels.pose", "odometry in (`ogf.odometry_t` or `bot_core.pose_t`)", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.pose_channel; }));
  k.push_back(textKey("channels.delta", "map changes out (`ogf.map_delta_t`)", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.delta_channel; }));
  k.push_back(textKey("channels.request", "keyframe requests in", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.request_channel; }));
  k.push_back(textKey("channels.status", "the mapper's status out, every `status_interval_s`", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.status_channel; }));
  k.push_back(textKey("channels.corrected_pose", "corrected poses out (with `pose_correction.mode` other than `none`)",
                      kMapper, kChannelLength, [](auto& o) -> auto& { return o.corrected_pose_channel; }));
  k.push_back(textKey("channels.query", "map queries in; answers on `<channel>_REPLY`", kMapper, kServiceChannelLength,
                      [](auto& o) -> auto& { return o.query_channel; }));
  k.push_back(textKey("channels.command", "map commands in; answers on `<channel>_REPLY`", kMapper,
                      kServiceChannelLength, [](auto& o) -> auto& { return o.command_channel; }));
  k.push_back(textKey("channels.nav_grid", "the 2-D navigation grid out (`ogf.nav_grid_t`)", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.nav_grid_channel; }));
  k.push_back(textKey("channels.nav_request", "navigation grid keyframe requests in", kMapper, kChannelLength,
                      [](auto& o) -> auto& { return o.nav_request_channel; }));
}

// Which clock the odometry is on and where the body's pose comes from.
void declarePoseSource(std::vector<ConfigKey>& k) {
  k.push_back(choiceKey<ScanTimeBase>(
      "time_base",
      "the clock of the odometry's `utime`: `device` (the scan's device time), `host` (its receive time) or "
      "`auto`: device for scans whose device time is GPS/PPS-locked UTC, host for the others (`--time-base`, "
      "`ogf-map --time`)",
      kAll, {{"auto", ScanTimeBase::kAuto}, {"device", ScanTimeBase::kDevice}, {"host", ScanTimeBase::kHost}},
      [](auto& o) -> auto& { return o.time_base; }));
  k.push_back(choiceKey<PoseSource>(
      "pose_source",
      "where the body's pose comes from: `odometry` (the messages on `channels.pose`, or the odometry file "
      "offline) or `static`, a sensor that does not move, at `static_pose` (`--static`)",
      kAll, {{"odometry", PoseSource::kOdometry}, {"static", PoseSource::kStatic}},
      [](auto& o) -> auto& { return o.pose_source; }));
  k.push_back(poseKey("static_pose",
                      "with `pose_source: static`, the body's pose in the map frame: `translation` (m) and `rpy` "
                      "(rad) or `quaternion` [w, x, y, z]",
                      kOffline, [](auto& o) -> auto& { return o.static_pose; }));
  k.back().default_note = "identity";
}

// Where and how often the map is kept on disk.
void declarePersistence(std::vector<ConfigKey>& k) {
  k.push_back({"state_dir", "text", "",
               "snapshots and the journal; when empty, `$STATE_DIRECTORY` (systemd's `StateDirectory=`) if set, "
               "else the map lives in memory only (`--state-dir`, `--in-memory`)",
               kMapper,
               [](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
                 auto v = readText(n, where);
                 if (!v) return v.error();
                 o.state_dir = *v;
                 return okStatus();
               },
               [](const MapperOptions& o) { return yamlText(o.state_dir.string()); },
               "`\"\"` (`$STATE_DIRECTORY`)"});
  k.push_back(numberKey("snapshot_interval_s", "s",
                        "how often the map is saved; a restart after a crash replays the scans since the last "
                        "snapshot, about 10 s at 20 s "
                        "([performance.md](performance.md#restart-after-a-crash))",
                        kMapper, positive, [](auto& o) -> auto& { return o.snapshot_interval_s; }));
  k.push_back(numberKey("page_out_distance_m", "m",
                        "map regions farther from the sensor wait in `<state_dir>/pages` and come back when a scan "
                        "reaches them; the same map, bit for bit; 0: all in memory "
                        "([mapping.md](mapping.md#the-daemon-ogf-mapper))",
                        kMapper, nonNegative, [](auto& o) -> auto& { return o.page_out_distance_m; }));
}

// How often the whole map and the status go out unasked.
void declarePublishing(std::vector<ConfigKey>& k) {
  k.push_back(numberKey("keyframe_interval_s", "s", "how often the whole map is sent unasked", kMapper, positive,
                        [](auto& o) -> auto& { return o.keyframe_interval_s; }));
  k.push_back(numberKey("status_interval_s", "s", "how often the status is published", kMapper, positive,
                        [](auto& o) -> auto& { return o.status_interval_s; }));
}

// The map section: the cell size, the measurements' range and the sensor's mounting.
void declareMap(std::vector<ConfigKey>& k) {
  ConfigKey resolution = numberKey("map.resolution", "m", "cell edge", kAll, positive,
                                   [](auto& o) -> auto& { return o.map.fusion.measurement.resolution_m; });
  // Fusion and filter share the cell size.
  resolution.read = [inner = resolution.read](const YAML::Node& n, MapperOptions& o, const Locate& where) {
    auto st = inner(n, o, where);
    if (st) o.map.setResolution(o.map.fusion.measurement.resolution_m);
    return st;
  };
  k.push_back(std::move(resolution));
  k.push_back(numberKey("map.min_range", "m", "returns closer are ignored", kAll, nonNegative,
                        [](auto& o) -> auto& { return o.map.fusion.measurement.min_range_m; }));
  k.push_back(numberKey("map.max_range", "m", "rays longer are cut here and mark free cells only", kAll, positive,
                        [](auto& o) -> auto& { return o.map.fusion.measurement.max_range_m; }));
  k.push_back(boolKey("map.free_space_for_no_return",
                      "a beam without a return marks free cells up to `map.max_range` (a missing return can be a "
                      "black or shiny surface, not empty space)",
                      kAll, [](auto& o) -> auto& { return o.map.fusion.measurement.free_space_for_no_return; }));
  k.push_back(poseKey("map.extrinsic",
                      "sensor → body: `translation` (m) and `rpy` (rad, R = Rz(yaw) Ry(pitch) Rx(roll)) or "
                      "`quaternion` [w, x, y, z]",
                      kAll, [](auto& o) -> auto& { return o.map.fusion.extrinsic; }));
  k.back().default_note = "identity";
}

// The filter section: the OGF's kernel, thresholds and speed-ups.
void declareFilter(std::vector<ConfigKey>& k) {
  k.push_back(derivedNumberKey("filter.sigma", "m",
                               "how far a measurement's evidence spreads, the kernel's σ "
                               "([mapping.md](mapping.md))",
                               kAll, "resolution / 2", [](auto& o) -> auto& { return o.map.filter.kernelSigma; }));
  k.push_back(derivedNumberKey("filter.amplitude", "", "the kernel's amplitude", kAll, "1 / (σ √(2π))",
                               [](auto& o) -> auto& { return o.map.filter.kernelAmplitude; }));
  k.push_back(derivedNumberKey("filter.stencil_radius", "cells", "R, the reach of the covariance stencil", kAll,
                               "√2 up to σ = cell / 2",
                               [](auto& o) -> auto& { return o.map.filter.stencilRadius; }));
  k.push_back(integerKey(
      "filter.stencil_manhattan_radius", "cells",
      "L: offsets of Manhattan length up to L are in the stencil too; 0: none (with compact storage, a "
      "faster and leaner map: [mapping.md](mapping.md#a-leaner-stencil-for-compact-storage))",
      kAll, 0, 64, [](auto& o) -> auto& { return o.map.filter.stencilManhattanRadius; }));
  k.push_back(derivedNumberKey("filter.taper_support", "cells", "support of the taper that keeps the prior definite",
                               kAll, "the longest certified", [](auto& o) -> auto& { return o.map.filter.taperSupport; }));
  k.push_back(numberKey("filter.occupied_threshold", "", "probability above which a cell is occupied (r_o, eq. 3)",
                        kAll, probability, [](auto& o) -> auto& { return o.map.filter.occupiedThreshold; }));
  k.push_back(numberKey("filter.free_threshold", "", "probability below which a cell is free (r_f, eq. 3)", kAll,
                        probability, [](auto& o) -> auto& { return o.map.filter.freeThreshold; }));
  k.push_back(numberKey("filter.skip_tolerance", "", "an update changing the cell's mean and variance less is skipped",
                        kAll, nonNegative, [](auto& o) -> auto& { return o.map.filter.skipTolerance; }));
  k.push_back(numberKey("filter.clamp_z", "",
                        "skip measurements that agree with a cell beyond this probit z (speed; 0: the exact filter)",
                        kAll, nonNegative, [](auto& o) -> auto& { return o.map.filter.clampZ; }));
  k.push_back(numberKey("filter.free_clamp_z", "", "the same for free measurements, most of a scan's (0: `clamp_z`)",
                        kAll, nonNegative, [](auto& o) -> auto& { return o.map.filter.freeClampZ; }));
  k.push_back(choiceKey<filter::OccupiedPriority>(
      "filter.occupied_priority",
      "`map`: a cell once hit ignores free measurements until `free_release_scans` free scans in a row (`scan`: "
      "the exact filter; [mapping.md](mapping.md#occupied-priority))",
      kAll, {{"map", filter::OccupiedPriority::kMap}, {"scan", filter::OccupiedPriority::kScan}},
      [](auto& o) -> auto& { return o.map.filter.occupiedPriority; }));
  k.push_back(integerKey("filter.free_release_scans", "", "see `occupied_priority`; 0: never released; `ogf-mapper` with several `sources` counts this many for each (at most 127)", kAll, 0,
                         filter::kMaxFreeRelease, [](auto& o) -> auto& { return o.map.filter.freeReleaseCount; }));
  k.push_back(choiceKey<filter::CovarianceStorage>(
      "filter.covariance",
      "`compact`: 7 bytes a cell, covariances rebuilt from the prior; `banded`: covariances stored, eq. (5) "
      "exactly inside the band, 57 bytes ([mapping.md](mapping.md#covariance-storage))",
      kAll, {{"compact", filter::CovarianceStorage::kCompact}, {"banded", filter::CovarianceStorage::kBanded}},
      [](auto& o) -> auto& { return o.map.filter.covariance; }));
  k.push_back(integerKey("filter.threads", "",
                         "filter threads (the map is identical for any count): the updates, the batch's "
                         "grouping and ordering and the change detection run on all of them; 2 filter 0.1 m "
                         "street scans 1.6x as fast as 1 on a 2-CPU virtual machine, 1.4x with the change "
                         "detection ([performance.md](performance.md#where-the-time-goes-in-a-scan))",
                         kAll, 1, 256, [](auto& o) -> auto& { return o.map.filter.threads; }));
}

// The fusion section: how scans wait for odometry and which poses and times are believed.
void declareFusion(std::vector<ConfigKey>& k) {
  k.push_back(numberKey("fusion.max_pose_wait_s", "s", "how long a scan waits for odometry", kMapper, nonNegative,
                        [](auto& o) -> auto& { return o.map.fusion.pending.max_pose_wait_s; }));
  k.push_back(integerKey("fusion.pose_buffer_capacity", "", "odometry poses kept (offline: the whole file)", kMapper,
                         2, 100'000'000, [](auto& o) -> auto& { return o.map.fusion.pose_buffer.capacity; }));
  k.push_back(integerKey("fusion.max_pending_scans", "",
                         "scans waiting for odometry; the oldest whole scans are dropped beyond it", kMapper, 1,
                         1'000'000, [](auto& o) -> auto& { return o.map.fusion.pending.max_pending_scans; }));
  k.push_back(integerKey("fusion.max_pending_points", "", "the same bound in points", kMapper, 1, 1'000'000'000,
                         [](auto& o) -> auto& { return o.map.fusion.pending.max_pending_points; }));
  k.push_back(numberKey("fusion.max_pose_jump.translation_m", "m",
                        "a larger step between poses splits the trajectory; a scan spanning it is dropped", kAll,
                        positive, [](auto& o) -> auto& { return o.map.fusion.pose_buffer.jump_translation_m; }));
  k.push_back(numberKey("fusion.max_pose_jump.rotation_rad", "rad", "the same for rotation", kAll, positive,
                        [](auto& o) -> auto& { return o.map.fusion.pose_buffer.jump_rotation_rad; }));
  k.push_back(numberKey("fusion.quaternion_tolerance", "",
                        "largest difference of a pose quaternion's norm from 1 accepted (then normalised); beyond it the pose is refused", kAll,
                        positive, [](auto& o) -> auto& { return o.map.fusion.pose_buffer.quaternion_tolerance; }));
  k.push_back(numberKey("fusion.max_time_ahead_s", "s", "a pose or scan this far ahead of its stream is refused",
                        kMapper, positive, [](auto& o) -> auto& { return o.map.fusion.time_sanity.max_ahead_s; }));
  k.push_back(numberKey("fusion.max_time_behind_s", "s", "... or this far behind it", kMapper, positive,
                        [](auto& o) -> auto& { return o.map.fusion.time_sanity.max_behind_s; }));
  k.push_back(integerKey("fusion.clock_jump_messages", "",
                         "refused messages in a row that agree: the clock jumped, follow it", kMapper, 1, 1000,
                         [](auto& o) -> auto& { return o.map.fusion.time_sanity.follow_after; }));
}

// The pose_correction section: correcting drifting odometry with the lidar.
void declarePoseCorrection(std::vector<ConfigKey>& k) {
  std::vector<std::pair<std::string, slam::CorrectionMode>> modes;
  for (const auto m : {slam::CorrectionMode::kNone, slam::CorrectionMode::kScanMatch, slam::CorrectionMode::kRbpf})
    modes.emplace_back(std::string(slam::toString(m)), m);
  k.push_back(choiceKey<slam::CorrectionMode>(
      "pose_correction.mode",
      "`scan-match` or `rbpf` correct drifting odometry with the lidar before mapping ([slam.md](slam.md))",
      kOffline, modes, [](auto& o) -> auto& { return o.pose_correction.corrector.mode; }));
  k.push_back(integerKey("pose_correction.particles", "", "particles of `rbpf`", kOffline, 1, 10'000,
                         [](auto& o) -> auto& { return o.pose_correction.corrector.slam.particles; }));
  k.push_back(numberKey("pose_correction.band_z_min", "m", "bottom of the body-frame height band cut into the planar scan",
                        kOffline, anyNumber, [](auto& o) -> auto& { return o.pose_correction.projection.z_min_m; }));
  k.push_back(numberKey("pose_correction.band_z_max", "m", "top of that band", kOffline, anyNumber,
                        [](auto& o) -> auto& { return o.pose_correction.projection.z_max_m; }));
  k.push_back(integerKey("pose_correction.seed", "", "seed of `rbpf`'s random draws", kOffline, 0,
                         std::numeric_limits<long long>::max(),
                         [](auto& o) -> auto& { return o.pose_correction.corrector.slam.seed; }));
}

// The map services (OGF_MAP_QUERY, OGF_MAP_COMMAND): who may command the mapper, where exports go, and how
// much of the mapping thread queries and commands may take (docs/reliability.md, "Map services").
void declareServices(std::vector<ConfigKey>& k) {
  k.push_back(boolKey("services.commands_enabled",
                      "`save`, `reset` and `export` are carried out only when true, and then each needs a MAC made "
                      "with `services.key_file` (`ogf-map-query --key`)",
                      kMapper, [](auto& o) -> auto& { return o.services.commands_enabled; }));
  k.push_back(servicesPathKey("services.key_file",
                      "the commands' key: 64 hex digits in a regular file of the mapper's user, mode 0600 "
                      "(`ogf-map-query keygen FILE` makes one); the mapper refuses to start with any other",
                      &ServicesOptions::key_file, ""));
  k.push_back(servicesPathKey("services.export_dir",
                      "exports are written only here, by plain file name, never replacing a file; never the state "
                      "directory itself",
                      &ServicesOptions::export_dir, "`\"\"` (`<state_dir>/exports`)"));
  k.push_back(integerKey("services.export_min_free_bytes", "bytes",
                         "an export that would leave less free space on its file system is refused", kMapper, 0,
                         std::numeric_limits<long long>::max(),
                         [](auto& o) -> auto& { return o.services.export_min_free_bytes; }));
  k.push_back(integerKey("services.max_query_cells", "cells",
                         "a box query over more cells is refused before any of the map is read or paged in", kMapper,
                         1, 100'000'000, [](auto& o) -> auto& { return o.services.max_query_cells; }));
  k.push_back(numberKey("services.budget_ms_per_scan", "ms",
                        "service work on the mapping thread between two scans; the queries and commands beyond it "
                        "wait for the next scan",
                        kMapper, positive, [](auto& o) -> auto& { return o.services.budget_ms_per_scan; }));
  k.push_back(integerKey("services.box_chunk_cells", "cells",
                         "cells of a box query summarised in one step (a larger box is answered over several scans)",
                         kMapper, 1000, 100'000'000, [](auto& o) -> auto& { return o.services.box_chunk_cells; }));
}

// A probability step: 0 (every change) up to, not including, 1.
std::optional<std::string> probabilityStep(double v) {
  return v >= 0 && v < 1 ? std::nullopt : std::optional<std::string>("must be 0 or more and below 1");
}

// The deltas section: what change of a cell goes out on OGF_MAP_DELTA, and how many bytes a second
// (docs/mapping.md, "The daemon: ogf-mapper").
void declareDeltas(std::vector<ConfigKey>& k) {
  k.push_back(numberKey("deltas.probability_step", "",
                        "a cell goes out when its class changes or its probability moves this far from the value "
                        "last published (slow drifts go out once they add up); 0: every change of the quantised "
                        "probability",
                        kMapper, probabilityStep, [](auto& o) -> auto& { return o.deltas.probability_step; }));
  k.push_back(numberKey("deltas.variance_step", "",
                        "also when its variance moves by more than this fraction of the published one; 0: variance "
                        "alone sends nothing",
                        kMapper, nonNegative, [](auto& o) -> auto& { return o.deltas.variance_step; }));
  k.push_back(integerKey("deltas.max_bytes_per_s", "bytes/s",
                         "bytes per second of the delta channel, keyframes included (a keyframe takes at most half "
                         "while it goes out); the cells beyond it wait, class changes first, for later updates; 0: "
                         "unbounded",
                         kMapper, 0, std::numeric_limits<long long>::max(),
                         [](auto& o) -> auto& { return o.deltas.max_bytes_per_s; }));
  k.push_back(numberKey("deltas.burst_s", "s", "the most the delta channel sends at once, in seconds of its rate",
                        kMapper, positive, [](auto& o) -> auto& { return o.deltas.burst_s; }));
  k.push_back(numberKey("deltas.max_wait_s", "s",
                        "the most cells that wait for the rate, in seconds of it; a change beyond them marks its "
                        "8 x 8 slab of cells stale, sent from the map as it is then once the waiting cells drain "
                        "(bounds the memory and time of a map that changes faster than the rate carries)",
                        kMapper, positive, [](auto& o) -> auto& { return o.deltas.max_wait_s; }));
}

// A fraction in [0, 1].
std::optional<std::string> fraction(double v) {
  return v >= 0 && v <= 1 ? std::nullopt : std::optional<std::string>("must be 0 to 1");
}

// The nav section: the height band the 2-D navigation grid is projected from (live on channels.nav_grid,
// offline by ogf-map --export-nav) and how often it goes out (docs/navigation.md).
void declareNav(std::vector<ConfigKey>& k) {
  k.push_back(boolKey("nav.enabled", "publish the 2-D navigation grid on `channels.nav_grid`", kMapper,
                      [](auto& o) -> auto& { return o.nav.enabled; }));
  k.push_back(numberKey("nav.floor_z", "m", "height of the floor in the map frame", kAll, anyNumber,
                        [](auto& o) -> auto& { return o.nav.band.floor_z; }));
  k.push_back(numberKey("nav.min_height", "m",
                        "the band starts this far above the floor (cells whose centre is lower are floor, not obstacle)",
                        kAll, anyNumber, [](auto& o) -> auto& { return o.nav.band.min_height; }));
  k.push_back(numberKey("nav.max_height", "m", "the band ends this far above the floor: the robot's height", kAll,
                        anyNumber, [](auto& o) -> auto& { return o.nav.band.max_height; }));
  k.push_back(numberKey("nav.min_free_fraction", "",
                        "a column with no occupied cell in the band is free when at least this fraction of its "
                        "layers holds a free cell, else unknown",
                        kAll, fraction, [](auto& o) -> auto& { return o.nav.band.min_free_fraction; }));
  k.push_back(numberKey("nav.update_interval_s", "s", "changed tiles of the grid go out at most this often", kMapper,
                        positive, [](auto& o) -> auto& { return o.nav.update_interval_s; }));
  k.push_back(numberKey("nav.keyframe_interval_s", "s", "how often the whole grid is sent unasked", kMapper,
                        positive, [](auto& o) -> auto& { return o.nav.keyframe_interval_s; }));
}

// Every key, section after section, in the order --print-config prints them.
std::vector<ConfigKey> declare() {
  std::vector<ConfigKey> k;
  declareBus(k);
  declarePoseSource(k);
  k.push_back(sourcesKey());
  declarePersistence(k);
  declarePublishing(k);
  declareDeltas(k);
  declareNav(k);
  declareMap(k);
  declareFilter(k);
  declareFusion(k);
  declarePoseCorrection(k);
  declareServices(k);
  return k;
}

// Keys spelt another way, refused naming the key to use.
constexpr RenamedKey kRenamed[] = {
    {"resolution", "map.resolution"},
    {"min_range", "map.min_range"},
    {"max_range", "map.max_range"},
    {"free_space_for_no_return", "map.free_space_for_no_return"},
    {"extrinsic", "map.extrinsic"},
    {"filter.kernel_sigma", "filter.sigma"},
    {"filter.kernel_amplitude", "filter.amplitude"},
};

}  // namespace

const std::vector<ConfigKey>& keys() {
  static const std::vector<ConfigKey> all = declare();
  return all;
}

std::span<const RenamedKey> renamedKeys() { return kRenamed; }

}  // namespace ogf::mapper_daemon::schema
