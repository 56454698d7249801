// The --config file of the offline programs that map (ogf-map, ogf-eval): ogf-mapper's configuration file,
// read by the same reader (ogf/mapper_daemon/mapper_options.hpp), so one file configures every program.
// The keys a program does not use (the bus, the channels, the state directory, the live queues) are
// accepted and listed, for the program to say once that it ignores them.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/mapper_daemon/mapper_options.hpp>

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ogf::map_io {

struct OfflineConfig {
  mapper_daemon::MapperOptions options;  // the defaults with the file's keys applied
  std::vector<std::string> keys_read;    // every key the file set ("map.resolution", "channels.scan")
  std::vector<std::string> unused_keys;  // those of them the program does not use

  bool sets(std::string_view key) const;
  // "ogf-map does not use channels.scan, state_dir (ogf-mapper's): ignored"; "" when every key is used.
  std::string unusedNote(std::string_view program) const;
};

// Reads the file at `path` for the program `user` (a mapper_daemon::ConfigUser bit) and validates it as
// ogf-mapper does. Errors name the file, the line and the key.
Result<OfflineConfig> readOfflineConfig(const std::filesystem::path& path, mapper_daemon::ConfigUser user);

}  // namespace ogf::map_io
