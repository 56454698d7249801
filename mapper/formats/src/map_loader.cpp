// Loading a map file or a daemon snapshot: see map_loader.hpp.
#include "ogf/map_formats/map_loader.hpp"

#include <ogf/filter/map_file.hpp>
#include <ogf/persistence/map_pager.hpp>
#include <ogf/persistence/state_directory.hpp>

#include <fstream>
#include <iterator>
#include <vector>

namespace ogf::map_formats {

Result<LoadedMap> loadOgfMap(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path.string() + ": cannot open"};
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::span<const std::byte> raw(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size());
  if (auto snap = persistence::decodeSnapshot(raw, path.string())) {
    auto map = filter::decodeMap(snap->map_bytes, path.string());
    if (!map) return Error{path.string() + ": snapshot holds a bad map: " + map.error().message};
    if (!snap->pages.empty()) {
      // The rest of the map, in the pages beside the snapshot; a map with a region missing is refused.
      const auto dir = path.parent_path() / "pages";
      auto pager = persistence::MapPager::open(dir);
      if (!pager) return Error{path.string() + ": its pages: " + pager.error().message};
      auto damage = pager->adopt(snap->pages, *map);
      if (damage.empty()) damage = pager->bringInAll(*map);
      if (!damage.empty()) return Error{path.string() + ": " + damage.front().reason};
    }
    return LoadedMap{std::move(*map), "snapshot", snap->seq};
  } else {
    auto map = filter::decodeMap(bytes, path.string());
    if (map) return LoadedMap{std::move(*map), "map file", -1};
    return Error{path.string() + ": neither a map file (" + map.error().message + ") nor a snapshot (" +
                 snap.error().message + ")"};
  }
}

}  // namespace ogf::map_formats
