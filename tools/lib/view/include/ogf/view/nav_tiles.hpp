// The 2-D navigation grid as ogf-view's browsers have it: a copy of the NavReceiver's tiles, so that a tick
// sends only the tiles whose values changed (a keyframe that changes little sends little), and a browser
// that joins gets every tile. At most kMaxNavTiles tiles are kept and drawn: the receiver takes any tile a
// well-formed message names, and the copy and the page must stay bounded whatever arrives on the bus.
#pragma once

#include <cstddef>
#include <map>
#include <vector>

#include "ogf/navigation/nav_receiver.hpp"
#include "ogf/view/nav_frame.hpp"

namespace ogf::view {

// 16 384 tiles of 32 × 32 columns: 32 MiB of values, 1.3 km² at 0.2 m.
inline constexpr std::size_t kMaxNavTiles = 16384;

class NavTiles {
 public:
  explicit NavTiles(std::size_t max_tiles = kMaxNavTiles) : max_tiles_(max_tiles) {}

  // Brings the copy to the receiver's tiles: returns the tiles that appeared or changed, and those gone as
  // tiles of unknown columns, sorted. Tiles beyond the bound are left out (notDrawn()).
  std::vector<NavTile> follow(const navigation::NavReceiver& receiver);
  // Every tile held, sorted.
  std::vector<NavTile> all() const;
  std::size_t size() const { return tiles_.size(); }
  // Known tiles of the receiver left out at the last follow() for the bound.
  std::size_t notDrawn() const { return not_drawn_; }

 private:
  std::size_t max_tiles_;
  std::map<navigation::TileKey, NavTile> tiles_;
  std::size_t not_drawn_ = 0;
};

}  // namespace ogf::view
