// Loads an OGF map (what ogf-map exports and ogf-eval scores) from either file the project writes: a filter
// map file (ogf-map --out, filter::saveMapFile) or the mapper daemon's snapshot container
// (<state-dir>/snapshot.ogfs), told apart by their magic: the snapshot decoder is tried first and refuses
// anything without its magic.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/filter/banded_ogf.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

namespace ogf::map_formats {

struct LoadedMap {
  filter::BandedOgf map;
  std::string kind;        // "map file" or "snapshot"
  std::int64_t seq = -1;   // the snapshot's update sequence (-1 for a map file)
};

Result<LoadedMap> loadOgfMap(const std::filesystem::path& path);

}  // namespace ogf::map_formats
