// The declaration of the mapping programs' configuration keys (config_schema.cpp): the one source that
// mapper_options.cpp makes the YAML reader, --print-config and the table of keys in docs/configuration.md from.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/mapper_daemon/mapper_options.hpp"

namespace ogf::mapper_daemon::schema {

// Names a place in the file for an error: "mapper.yaml:7: map.extrinsic.rpy" for the node `at` and a
// sub-key of the key being read ("" for the key itself).
using Locate = std::function<std::string(const YAML::Node& at, std::string_view subkey)>;

struct ConfigKey {
  std::string path;     // dotted: "map.resolution"
  std::string type;     // as the table states it: "number", "integer", "text", "`auto`, `device` or `host`"
  std::string unit;     // "m", "s", "rad", "cells" or ""
  std::string meaning;  // one line of Markdown (links become plain text in YAML comments)
  unsigned used_by;     // ConfigUser bits
  // Reads and checks the value at `value` into `options`; an error names the place through `locate`.
  std::function<Status(const YAML::Node& value, MapperOptions& options, const Locate& locate)> read;
  // The value held in `options`, as YAML flow text that read() takes back.
  std::function<std::string(const MapperOptions& options)> show;
  // A default that is derived or resolved elsewhere, as the table states it ("resolution / 2"); "" when
  // the value itself says it.
  std::string default_note;
};

// Every key, in the order --print-config prints them (the keys of one section are contiguous).
const std::vector<ConfigKey>& keys();

// A key spelt another way (a flat file of map settings, the filter's field names), refused naming the key
// to use.
struct RenamedKey {
  std::string_view old_path;
  std::string_view new_path;
};
std::span<const RenamedKey> renamedKeys();

// A rigid transform's sub-keys (translation, rpy, quaternion) read into `pose` (those not given keep their
// values); errors name `prefix` + "." + the sub-key. showPose gives it back as YAML flow text.
Status readPose(const YAML::Node& node, const Locate& where, std::string_view prefix, fusion::ExtrinsicConfig& pose);
std::string showPose(const fusion::ExtrinsicConfig& pose);

// The `sources:` list (source_keys.cpp).
ConfigKey sourcesKey();

// A number as YAML text, as short as reads back to the same double.
std::string yamlNumber(double value);
// A text as a YAML scalar: plain when that reads back the same, else double-quoted.
std::string yamlText(const std::string& text);

}  // namespace ogf::mapper_daemon::schema
