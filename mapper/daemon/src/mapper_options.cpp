// The configuration file's reader, printer and table, all made from the keys of config_schema.cpp.
#include "ogf/mapper_daemon/mapper_options.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "config_schema.hpp"

namespace ogf::mapper_daemon {
namespace {

const schema::ConfigKey* findKey(std::string_view path) {
  for (const auto& k : schema::keys())
    if (k.path == path) return &k;
  return nullptr;
}

// Whether `path` names a section: some key lies below it.
bool isSection(std::string_view path) {
  for (const auto& k : schema::keys())
    if (k.path.size() > path.size() && k.path.compare(0, path.size(), path) == 0 && k.path[path.size()] == '.')
      return true;
  return false;
}

// The keys one level below `section` ("" = the top level), for an unknown key's error.
std::string keysIn(std::string_view section) {
  std::vector<std::string> names;
  const std::string prefix = section.empty() ? std::string() : std::string(section) + ".";
  for (const auto& k : schema::keys()) {
    if (k.path.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = k.path.substr(prefix.size());
    const std::string name = rest.substr(0, rest.find('.'));
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

struct Reader {
  const std::filesystem::path& path;
  MapperOptions& options;
  std::vector<std::string>* keys_read;

  std::string where(const YAML::Node& at, std::string_view key) const {
    return path.string() + ":" + std::to_string(at.Mark().line + 1) + ": " + std::string(key);
  }

  // The keys of the mapping `node`, the section `section` of the file.
  Status section(const YAML::Node& node, const std::string& section_path) {
    if (node.IsNull()) return okStatus();  // `filter:` with nothing under it
    if (!node.IsMap()) return Error::configuration(where(node, section_path.empty() ? "the top level" : section_path) + ": expected a mapping of keys");
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) return Error::configuration(where(kv.first, section_path) + ": a key must be a name");
      const std::string key = section_path.empty() ? kv.first.Scalar() : section_path + "." + kv.first.Scalar();
      if (const auto* k = findKey(key)) {
        const schema::Locate locate = [this, &key](const YAML::Node& at, std::string_view sub) {
          // A list's entry ("[1].name") follows its key without a dot.
          return where(at, sub.empty() ? key : key + (sub.front() == '[' ? "" : ".") + std::string(sub));
        };
        if (kv.second.IsNull()) return Error::configuration(where(kv.first, key) + ": needs a value");
        if (auto st = k->read(kv.second, options, locate); !st) return st;
        if (keys_read) keys_read->push_back(key);
      } else if (isSection(key)) {
        if (auto st = section(kv.second, key); !st) return st;
      } else {
        for (const auto& r : schema::renamedKeys())
          if (r.old_path == key) return Error::configuration(where(kv.first, key) + ": not a key here: use " + std::string(r.new_path));
        return Error::configuration(where(kv.first, key) + ": unknown key (" + (section_path.empty() ? "keys" : section_path) +
                     ": " + keysIn(section_path) + ")");
      }
    }
    return okStatus();
  }
};

// Markdown links as plain text, for YAML comments: "[docs/slam.md](docs/slam.md)" -> "docs/slam.md".
std::string plainText(const std::string& markdown) {
  std::string out;
  for (std::size_t i = 0; i < markdown.size(); ++i) {
    if (markdown[i] == '[') {
      const auto close = markdown.find("](", i);
      const auto end = close == std::string::npos ? std::string::npos : markdown.find(')', close);
      if (end != std::string::npos) {
        out += markdown.substr(i + 1, close - i - 1);
        i = end;
        continue;
      }
    }
    if (markdown[i] != '`') out += markdown[i];
  }
  return out;
}

std::vector<std::string> split(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (auto dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
    parts.push_back(path.substr(start, dot - start));
    start = dot + 1;
  }
  parts.push_back(path.substr(start));
  return parts;
}

std::string programsOf(unsigned used_by) {
  constexpr unsigned kAll = kUsedByMapper | kUsedByMap | kUsedByEval;
  if (used_by == kAll) return "all";
  std::string s;
  for (const auto& [bit, name] : {std::pair{kUsedByMapper, "ogf-mapper"}, std::pair{kUsedByMap, "ogf-map"},
                                  std::pair{kUsedByEval, "ogf-eval"}})
    if (used_by & bit) s += (s.empty() ? "" : ", ") + std::string(name);
  return s;
}

}  // namespace

Status MapperOptions::validate() const {
  if (auto st = map.validate(); !st) return Error::configuration("map: " + st.error().message);
  if (auto st = pose_correction.validate(); !st) return Error::configuration("pose_correction: " + st.error().message);
  if (auto st = static_pose.validate(); !st) return Error::configuration("static_pose: " + st.error().message);
  if (pose_source == PoseSource::kStatic && pose_correction.corrector.mode != slam::CorrectionMode::kNone)
    return Error::configuration("pose_correction.mode: needs a moving sensor with odometry (pose_source: odometry)");
  for (const auto* ch : {&scan_channel, &pose_channel, &delta_channel, &request_channel, &status_channel,
                         &corrected_pose_channel, &query_channel, &command_channel, &nav_grid_channel,
                         &nav_request_channel}) {
    if (ch->empty() || ch->size() > 63) return Error::configuration("channels: '" + *ch + "' must be 1 to 63 characters");
  }
  for (const auto* ch : {&query_channel, &command_channel}) {
    if (ch->size() > 57) return Error::configuration("channels: '" + *ch + "' must be 1 to 57 characters (its reply adds _REPLY)");
  }
  const auto sources_in_force = resolveSources(*this);
  if (!sources_in_force) return sources_in_force.error();
  if (pose_correction.corrector.mode != slam::CorrectionMode::kNone &&
      std::any_of(sources_in_force->begin(), sources_in_force->end(),
                  [&](const ResolvedSource& s) { return s.robot != sources_in_force->front().robot; }))
    return Error::configuration("pose_correction.mode: corrects one robot's odometry; the sources name several robots");
  if (!(snapshot_interval_s > 0)) return Error::configuration("snapshot_interval_s: must be > 0");
  if (!(page_out_distance_m >= 0) || !std::isfinite(page_out_distance_m))
    return Error::configuration("page_out_distance_m: must be >= 0 (0 keeps the whole map in memory)");
  if (!(keyframe_interval_s > 0)) return Error::configuration("keyframe_interval_s: must be > 0");
  if (!(status_interval_s > 0)) return Error::configuration("status_interval_s: must be > 0");
  if (auto st = nav.band.validate(map.filter.resolution); !st) return Error::configuration(st.error().message);
  if (!(nav.update_interval_s > 0)) return Error::configuration("nav.update_interval_s: must be > 0");
  if (!(nav.keyframe_interval_s > 0)) return Error::configuration("nav.keyframe_interval_s: must be > 0");
  if (!(test_drop_delta_fraction >= 0 && test_drop_delta_fraction < 1))
    return Error::configuration("test_drop_delta_fraction: must be in [0, 1)");
  if (!(test_drop_nav_fraction >= 0 && test_drop_nav_fraction < 1))
    return Error::configuration("test_drop_nav_fraction: must be in [0, 1)");
  // services:
  if (services.commands_enabled && services.key_file.empty())
    return Error::configuration("services.commands_enabled: needs services.key_file (ogf-map-query keygen FILE makes one)");
  if (services.max_query_cells < 1 || services.max_query_cells > 100'000'000)
    return Error::configuration("services.max_query_cells: must be 1 to 100000000");
  if (services.box_chunk_cells < 1000) return Error::configuration("services.box_chunk_cells: must be 1000 or more");
  if (!(services.budget_ms_per_scan > 0) || !std::isfinite(services.budget_ms_per_scan))
    return Error::configuration("services.budget_ms_per_scan: must be > 0");
  if (const auto exports = services.exportDirFor(state_dir); !exports.empty() && !state_dir.empty()) {
    // Compared resolved (links, '..') and without a trailing '/', so no spelling of the state directory passes.
    // A path the system cannot resolve (a name longer than it allows, a loop of links) is an error naming it.
    std::string unresolved;
    const auto resolved = [&](const std::filesystem::path& p, const char* field) {
      std::error_code ec;
      std::string s = std::filesystem::weakly_canonical(p, ec).lexically_normal().string();
      if (ec && unresolved.empty()) unresolved = std::string(field) + ": " + p.string() + ": " + ec.message();
      while (s.size() > 1 && s.back() == '/') s.pop_back();
      return std::filesystem::path(s);
    };
    const auto b = resolved(state_dir, "state_dir"), a = resolved(exports, "services.export_dir");
    if (!unresolved.empty()) return Error::configuration(unresolved);
    if (a == b || a == b / "pages")
      return Error::configuration("services.export_dir: " + exports.string() + " is the state directory's own; exports must never land among its files");
  }
  return okStatus();
}

std::filesystem::path ServicesOptions::exportDirFor(const std::filesystem::path& state_dir) const {
  if (!export_dir.empty()) return export_dir;
  if (state_dir.empty()) return {};
  return state_dir / "exports";
}

Status loadMapperOptions(const std::filesystem::path& path, MapperOptions& o, std::vector<std::string>* keys_read) {
  std::ifstream in(path);
  if (!in) return Error::configuration(path.string() + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();  // an empty file gives "", an empty configuration
  return parseMapperOptions(text.str(), path, o, keys_read);
}

Status parseMapperOptions(const std::string& yaml, const std::filesystem::path& path, MapperOptions& o,
                          std::vector<std::string>* keys_read) {
  // Any YAML exception the reading does not catch itself is still an error in this file, never an exception
  // out of the program's start-up.
  try {
    const YAML::Node root = YAML::Load(yaml);
    if (!root || root.IsNull()) return okStatus();
    return Reader{path, o, keys_read}.section(root, "");
  } catch (const YAML::Exception& e) {
    return Error::configuration(path.string() + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

unsigned configKeyUsers(std::string_view path) {
  const auto* k = findKey(path);
  return k ? k->used_by : 0U;
}

std::string mapperConfigYaml(const MapperOptions& options) {
  const MapperOptions defaults;
  std::ostringstream s;
  s << "# The mapping programs' configuration (YAML): ogf-mapper --config, ogf-map --config, ogf-eval --config.\n"
    << "# Every key is optional; shown with its value. Comments: unit; the programs that use the key\n"
    << "# (the others accept it and ignore it); its meaning.\n";
  std::vector<std::string> open;  // the sections the previous key was in
  for (const auto& k : schema::keys()) {
    const auto parts = split(k.path);
    const std::vector<std::string> sections(parts.begin(), parts.end() - 1);
    std::size_t same = 0;
    while (same < open.size() && same < sections.size() && open[same] == sections[same]) ++same;
    for (std::size_t d = same; d < sections.size(); ++d)
      s << std::string(2 * d, ' ') << sections[d] << ":\n";
    open = sections;
    std::string line = std::string(2 * sections.size(), ' ') + parts.back() + ": " + k.show(options);
    std::string comment = k.unit.empty() ? "" : k.unit + "; ";
    if (!k.default_note.empty() && k.show(options) == k.show(defaults)) comment += plainText(k.default_note) + "; ";
    comment += (k.used_by == (kUsedByMapper | kUsedByMap | kUsedByEval) ? std::string() : programsOf(k.used_by) + "; ") +
               plainText(k.meaning);
    line.resize(std::max<std::size_t>(line.size() + 1, 40), ' ');
    s << line << "# " << comment << "\n";
  }
  return s.str();
}

std::string mapperConfigMarkdown() {
  const MapperOptions defaults;
  std::ostringstream s;
  s << "| key | type | default | used by | meaning |\n|---|---|---|---|---|\n";
  for (const auto& k : schema::keys()) {
    std::string value = k.default_note.empty() ? "`" + k.show(defaults) + "`" + (k.unit.empty() ? "" : " " + k.unit)
                                               : k.default_note;
    s << "| `" << k.path << "` | " << k.type << " | " << value << " | " << programsOf(k.used_by) << " | " << k.meaning
      << " |\n";
  }
  return s.str();
}

}  // namespace ogf::mapper_daemon
