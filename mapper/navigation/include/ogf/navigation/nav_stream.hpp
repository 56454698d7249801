// The publishing side of OGF_NAV_GRID (ogf_nav_grid_t.lcm): turns the tiles a NavProjection refresh changed
// into nav_grid_t updates that each fit one UDP datagram, numbered like the 3-D deltas so a client tells a
// gap from a quiet grid, and cuts keyframes (every known tile) at a low rate and on request.
#pragma once

#include <ogf/nav_grid_t.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "ogf/navigation/nav_projection.hpp"

namespace ogf::navigation {

// Tiles per message: 24 tiles of 32 × 32 columns are 48 KiB of values, within one datagram with the header.
inline constexpr std::int32_t kMaxTilesPerMessage = 24;

class NavStream {
 public:
  explicit NavStream(std::int64_t map_id, std::int32_t max_tiles_per_message = kMaxTilesPerMessage)
      : map_id_(map_id), max_tiles_(max_tiles_per_message) {}

  // Update seq()+1 carrying `tiles` of `grid` as they are now (at least one message, in parts), each
  // stamped with the grid's checksum.
  std::vector<ogf::nav_grid_t> update(std::int64_t utime, const NavProjection& grid, std::span<const TileKey> tiles);
  // Every known tile of `grid` as a keyframe at seq() (kind KEYFRAME, base_seq -1), in parts.
  std::vector<ogf::nav_grid_t> keyframe(std::int64_t utime, const NavProjection& grid) const;

  // A new map: its id, numbering from `seq`.
  void reset(std::int64_t map_id, std::int64_t seq = 0) {
    map_id_ = map_id;
    seq_ = seq;
  }
  std::int64_t seq() const { return seq_; }
  std::int64_t mapId() const { return map_id_; }

 private:
  std::vector<ogf::nav_grid_t> split(std::int64_t utime, std::int8_t kind, std::int64_t base_seq,
                                     const NavProjection& grid, std::span<const TileKey> tiles) const;

  std::int64_t map_id_;
  std::int32_t max_tiles_;
  std::int64_t seq_ = 0;
};

}  // namespace ogf::navigation
