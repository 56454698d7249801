// The binary WebSocket frame that carries tiles of the 2-D navigation grid (OGF_NAV_GRID, nav_grid_t) to
// the page (web/index.html decodes it with typed arrays). Little-endian, every array 4-byte aligned:
//
//   offset 0   u32 magic "OGN1" (0x314E474F)
//   4          u32 flags: bit 0 = full (the page drops every tile before applying this frame)
//   8          u32 n: tiles in this frame
//   12         u32 tile_size: columns along each side of a tile (navigation::kTileSize)
//   16         f32 resolution, metres
//   20         f32 floor_z, metres in the map frame: the height the page draws the grid at
//   24         i32 tile[2n]     x, y of each tile
//              i8  cost[n · tile_size²]    0..100, -1 unknown; each tile row-major from its south-west column
//              i8  class[n · tile_size²]   -1 free, 0 unknown, +1 occupied
//
// 2 bytes a column, 2 KiB a tile of 32 × 32. A tile in a frame replaces the page's tile whole; a tile of
// unknown columns removes it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/navigation/nav_projection.hpp"

namespace ogf::view {

inline constexpr std::uint32_t kNavFrameMagic = 0x314E474F;
inline constexpr std::uint32_t kNavFrameFull = 1;
inline constexpr std::size_t kNavFrameHeaderBytes = 24;
inline constexpr std::size_t kNavTileColumns = static_cast<std::size_t>(navigation::kTileSize) * navigation::kTileSize;
// Tiles per frame: 512 tiles are 1 MiB, a quarter of what a browser may have waiting (kMaxWaitingBytes).
inline constexpr std::size_t kMaxNavTilesPerFrame = 512;

struct NavTile {
  navigation::TileKey key;
  std::vector<std::int8_t> cost;          // kNavTileColumns values
  std::vector<std::int8_t> column_class;  // kNavTileColumns values
};

// `tiles` cut into frames of at most `max_tiles`; only the first is marked full (when `full`). A full
// frame goes out even with no tile, so the page still clears.
std::vector<std::vector<std::uint8_t>> encodeNavFrames(std::span<const NavTile> tiles, bool full, double resolution,
                                                       double floor_z, std::size_t max_tiles = kMaxNavTilesPerFrame);

struct DecodedNavFrame {
  bool full = false;
  float resolution = 0.0f;
  float floor_z = 0.0f;
  std::vector<NavTile> tiles;
};

// The page's decoding, for tests and tools; nullopt when the bytes are not a well-formed frame.
std::optional<DecodedNavFrame> decodeNavFrame(std::span<const std::uint8_t> bytes);

}  // namespace ogf::view
