#include "ogf/navigation/nav_stream.hpp"

#include <algorithm>

namespace ogf::navigation {
std::vector<ogf::nav_grid_t> NavStream::update(std::int64_t utime, const NavProjection& grid,
                                               std::span<const TileKey> tiles) {
  ++seq_;
  return split(utime, ogf::nav_grid_t::KIND_UPDATE, seq_ - 1, grid, tiles);
}

std::vector<ogf::nav_grid_t> NavStream::keyframe(std::int64_t utime, const NavProjection& grid) const {
  const auto tiles = grid.knownTiles();
  return split(utime, ogf::nav_grid_t::KIND_KEYFRAME, -1, grid, tiles);
}

std::vector<ogf::nav_grid_t> NavStream::split(std::int64_t utime, std::int8_t kind, std::int64_t base_seq,
                                              const NavProjection& grid, std::span<const TileKey> tiles) const {
  const auto per = static_cast<std::size_t>(std::max(1, max_tiles_));
  const auto parts = std::max<std::size_t>(1, (tiles.size() + per - 1) / per);
  std::vector<ogf::nav_grid_t> out(parts);
  for (std::size_t p = 0; p < parts; ++p) {
    auto& m = out[p];
    m.utime = utime;
    m.map_id = map_id_;
    m.seq = seq_;
    m.base_seq = base_seq;
    m.kind = kind;
    m.part_index = static_cast<std::int32_t>(p);
    m.part_count = static_cast<std::int32_t>(parts);
    m.resolution = grid.resolution();
    m.floor_z = grid.band().floor_z;
    m.min_height = grid.band().min_height;
    m.max_height = grid.band().max_height;
    m.grid_checksum = static_cast<std::int64_t>(grid.checksum());
    m.tile_size = kTileSize;
    const auto first = p * per;
    const auto count = std::min(per, tiles.size() - std::min(first, tiles.size()));
    m.num_tiles = static_cast<std::int32_t>(count);
    m.num_columns = static_cast<std::int32_t>(count * kTileColumns);
    m.cost.resize(count * kTileColumns);
    m.column_class.resize(count * kTileColumns);
    for (std::size_t t = 0; t < count; ++t) {
      const auto& key = tiles[first + t];
      m.tile_x.push_back(key.x);
      m.tile_y.push_back(key.y);
      grid.tileValues(key, std::span(m.cost).subspan(t * kTileColumns, kTileColumns),
                      std::span(m.column_class).subspan(t * kTileColumns, kTileColumns));
    }
  }
  return out;
}

}  // namespace ogf::navigation
