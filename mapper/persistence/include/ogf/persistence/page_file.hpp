// A page: the blocks of one region of the map, held on disk while the robot is elsewhere (map_pager.hpp),
// and the region's cells as the delta stream last published them. Each block is stored as the filter
// stores it (BandedOgf::storedValues), so a page brings it back bit for bit. Little-endian:
//
//   "OGFPAGE1" | u32 version=2 | i32 region x, y, z | u32 blocks | u32 floats per block | u32 cells per block
//   | blocks × (i32 x, y, z | floats | one mark byte per cell)
//   | u32 published cells | cells × (i32 x, y, z | i16 probability | i8 class | f32 variance)
//   | u64 checksum(everything before)
// Version 1 pages (no published cells) are read too. The checksum is the map file's (map_checksum.hpp),
// which runs at memory speed.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/delta/published_cell.hpp"

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
  std::vector<delta::PublishedCell> published;
  bool has_published = true;  // decoded: false for a version 1 page, which predates the published cells
};

std::vector<std::byte> encodePage(const Page& page);
// Error naming `source`, the offset and the field when the bytes are truncated, corrupt or inconsistent.
Result<Page> decodePage(std::span<const std::byte> bytes, const std::string& source);

}  // namespace ogf::persistence
