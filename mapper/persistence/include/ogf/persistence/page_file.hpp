// A page: the blocks of one region of the map, held on disk while the robot is elsewhere (map_pager.hpp).
// Each block is stored as the filter stores it (BandedOgf::storedValues), so a page brings it back bit for
// bit. Little-endian:
//
//   "OGFPAGE1" | u32 version=1 | i32 region x, y, z | u32 blocks | u32 floats per block | u32 cells per block
//   | blocks × (i32 x, y, z | floats | one mark byte per cell) | u64 checksum(everything before)
// The checksum is the map file's (map_checksum.hpp), which runs at memory speed.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"

namespace ogf::persistence {

struct PageBlock {
  CellKey key;
  std::vector<float> stored;
  std::vector<std::uint8_t> marks;
};

struct Page {
  CellKey region;
  std::uint32_t floats_per_block = 0;
  std::uint32_t cells_per_block = 0;
  std::vector<PageBlock> blocks;
};

std::vector<std::byte> encodePage(const Page& page);
// Error naming `source`, the offset and the field when the bytes are truncated, corrupt or inconsistent.
Result<Page> decodePage(std::span<const std::byte> bytes, const std::string& source);

}  // namespace ogf::persistence
