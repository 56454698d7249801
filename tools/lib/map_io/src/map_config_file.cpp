#include "ogf/map_io/map_config_file.hpp"

#include <algorithm>

namespace ogf::map_io {

bool OfflineConfig::sets(std::string_view key) const {
  return std::find(keys_read.begin(), keys_read.end(), key) != keys_read.end();
}

std::string OfflineConfig::unusedNote(std::string_view program) const {
  if (unused_keys.empty()) return {};
  std::string keys;
  for (const auto& k : unused_keys) keys += (keys.empty() ? "" : ", ") + k;
  return std::string(program) + " does not use " + keys + " (ogf-mapper's): ignored";
}

Result<OfflineConfig> readOfflineConfig(const std::filesystem::path& path, mapper_daemon::ConfigUser user) {
  OfflineConfig c;
  if (auto st = mapper_daemon::loadMapperOptions(path, c.options, &c.keys_read); !st) return st.error();
  if (auto st = c.options.validate(); !st) return Error::configuration(path.string() + ": " + st.error().message);
  for (const auto& k : c.keys_read)
    if ((mapper_daemon::configKeyUsers(k) & user) == 0) c.unused_keys.push_back(k);
  return c;
}

}  // namespace ogf::map_io
