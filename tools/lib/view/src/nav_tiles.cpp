#include "ogf/view/nav_tiles.hpp"

#include <algorithm>
#include <set>

namespace ogf::view {
namespace {

NavTile unknownTile(const navigation::TileKey& key) {
  return {key, std::vector<std::int8_t>(kNavTileColumns, navigation::kUnknownCost),
          std::vector<std::int8_t>(kNavTileColumns, navigation::kClassUnknown)};
}

}  // namespace

std::vector<NavTile> NavTiles::follow(const navigation::NavReceiver& receiver) {
  std::vector<NavTile> changed;
  const auto known = receiver.knownTiles();  // sorted
  std::set<navigation::TileKey> keep;
  not_drawn_ = 0;
  NavTile now = unknownTile({});
  for (const auto& key : known) {
    auto it = tiles_.find(key);
    if (it == tiles_.end() && tiles_.size() >= max_tiles_) {
      ++not_drawn_;
      continue;
    }
    keep.insert(key);
    now.key = key;
    receiver.tileValues(key, now.cost, now.column_class);
    if (it != tiles_.end() && it->second.cost == now.cost && it->second.column_class == now.column_class) continue;
    tiles_[key] = now;
    changed.push_back(now);
  }
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    if (keep.count(it->first) != 0) {
      ++it;
      continue;
    }
    changed.push_back(unknownTile(it->first));
    it = tiles_.erase(it);
  }
  std::sort(changed.begin(), changed.end(), [](const NavTile& a, const NavTile& b) { return a.key < b.key; });
  return changed;
}

std::vector<NavTile> NavTiles::all() const {
  std::vector<NavTile> out;
  out.reserve(tiles_.size());
  for (const auto& [key, tile] : tiles_) out.push_back(tile);
  return out;
}

}  // namespace ogf::view
