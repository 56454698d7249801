// Loading a map file or a daemon snapshot: see map_loader.hpp.
#include "ogf/map_formats/map_loader.hpp"

#include <ogf/common/read_file.hpp>
#include <ogf/filter/map_file.hpp>
#include <ogf/persistence/map_pager.hpp>
#include <ogf/persistence/state_directory.hpp>
#include <vector>

namespace ogf::map_formats {

Result<LoadedMap> loadOgfMap(const std::filesystem::path& path) {
  auto bytes = readWholeFile(path);
  if (!bytes) return bytes.error();
  const std::span<const std::byte> raw(*bytes);
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
    auto map = filter::decodeMap({reinterpret_cast<const std::uint8_t*>(bytes->data()), bytes->size()},
                                 path.string());
    if (map) return LoadedMap{std::move(*map), "map file", -1};
    return Error{path.string() + ": neither a map file (" + map.error().message + ") nor a snapshot (" +
                 snap.error().message + ")"};
  }
}

}  // namespace ogf::map_formats
