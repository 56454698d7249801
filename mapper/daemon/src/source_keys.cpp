// The configuration's `sources:` list (source_options.hpp): each entry a mapping of the source's fields,
// read with the file and line of the field that is wrong, and printed back as YAML flow text.
#include <set>

#include "config_schema.hpp"

namespace ogf::mapper_daemon::schema {
namespace {

constexpr const char* kFields = "name, robot, scan_channel, packet_channel, calibration, pose_channel, time_base, extrinsic";

Result<adapters::ScanTimeBase> readTimeBase(const std::string& text) {
  if (text == "auto") return adapters::ScanTimeBase::kAuto;
  if (text == "device") return adapters::ScanTimeBase::kDevice;
  if (text == "host") return adapters::ScanTimeBase::kHost;
  return Error::configuration("expected one of 'auto', 'device', 'host', got '" + text + "'");
}

std::string timeBaseName(adapters::ScanTimeBase base) {
  switch (base) {
    case adapters::ScanTimeBase::kDevice:
      return "device";
    case adapters::ScanTimeBase::kHost:
      return "host";
    case adapters::ScanTimeBase::kAuto:
      break;
  }
  return "auto";
}

// One field of an entry; `at` names it in errors ("mapper.yaml:7: sources[1].name").
Status readField(const std::string& field, const YAML::Node& value, const std::string& at, const Locate& where,
                 SourceOptions& source) {
  if (field == "extrinsic") {
    fusion::ExtrinsicConfig pose;
    if (auto st = readPose(value, where, at, pose); !st) return st;
    source.extrinsic = pose;
    return okStatus();
  }
  if (!value.IsScalar()) return Error::configuration(where(value, at) + ": expected text");
  const std::string& text = value.Scalar();
  if (field == "name") {
    source.name = text;
  } else if (field == "robot") {
    source.robot = text;
  } else if (field == "scan_channel") {
    source.scan_channel = text;
  } else if (field == "packet_channel") {
    source.packet_channel = text;
  } else if (field == "calibration") {
    source.calibration = text;
  } else if (field == "pose_channel") {
    source.pose_channel = text;
  } else if (field == "time_base") {
    auto base = readTimeBase(text);
    if (!base) return Error::configuration(where(value, at) + ": " + base.error().message);
    source.time_base = *base;
  }
  return okStatus();
}

Status readEntry(const YAML::Node& entry, std::size_t index, const Locate& where, SourceOptions& source) {
  const std::string at = "[" + std::to_string(index) + "]";
  if (!entry.IsMap()) return Error::configuration(where(entry, at) + ": expected a mapping of " + kFields);
  static const std::set<std::string> known = {"name",         "robot",     "scan_channel", "packet_channel",
                                              "calibration",  "pose_channel", "time_base", "extrinsic"};
  for (const auto& kv : entry) {
    const std::string field = kv.first.IsScalar() ? kv.first.Scalar() : std::string("?");
    if (known.count(field) == 0)
      return Error::configuration(where(kv.first, at + "." + field) + ": unknown key (" + kFields + ")");
    if (kv.second.IsNull()) return Error::configuration(where(kv.first, at + "." + field) + ": needs a value");
    if (auto st = readField(field, kv.second, at + "." + field, where, source); !st) return st;
  }
  if (source.name.empty()) return Error::configuration(where(entry, at) + ": needs a name");
  return okStatus();
}

std::string showEntry(const SourceOptions& s) {
  std::string out = "{name: " + yamlText(s.name) + ", robot: " + yamlText(s.robot);
  if (!s.scan_channel.empty()) out += ", scan_channel: " + yamlText(s.scan_channel);
  if (!s.packet_channel.empty()) out += ", packet_channel: " + yamlText(s.packet_channel);
  if (!s.calibration.empty()) out += ", calibration: " + yamlText(s.calibration.string());
  if (!s.pose_channel.empty()) out += ", pose_channel: " + yamlText(s.pose_channel);
  if (s.time_base) out += ", time_base: " + timeBaseName(*s.time_base);
  if (s.extrinsic) out += ", extrinsic: " + showPose(*s.extrinsic);
  return out + "}";
}

}  // namespace

ConfigKey sourcesKey() {
  return {"sources",
          "list of {" + std::string(kFields) + "}",
          "",
          "several lidars and robots into one map ([architecture.md](architecture.md), \"Several "
          "sources\"); each entry's `scan_channel` (or `packet_channel`, decoded here with its `calibration`), "
          "`pose_channel`, `time_base` and `extrinsic` default to `channels.*`, `time_base` and `map.extrinsic`; "
          "`[]`: one source on `channels.scan`",
          kUsedByMapper,
          [](const YAML::Node& n, MapperOptions& o, const Locate& where) -> Status {
            if (!n.IsSequence()) return Error::configuration(where(n, "") + ": expected a list of sources");
            std::vector<SourceOptions> sources;
            for (std::size_t i = 0; i < n.size(); ++i) {
              SourceOptions source;
              if (auto st = readEntry(n[i], i, where, source); !st) return st;
              sources.push_back(std::move(source));
            }
            o.sources = std::move(sources);
            return okStatus();
          },
          [](const MapperOptions& o) {
            std::string out = "[";
            for (const auto& s : o.sources) out += (out.size() > 1 ? ", " : "") + showEntry(s);
            return out + "]";
          },
          ""};
}

}  // namespace ogf::mapper_daemon::schema
