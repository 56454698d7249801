// The banded map on disk. A header (magic, version, dimensions, resolution, kernel σ and amplitude, stencil
// R and L, taper support, thresholds, skip tolerance, clamps and occupied priority, block layout, block
// count), a 64-bit checksum of the payload and one of the header, then every block (key, its floats, its
// cell marks) in key order; all little-endian. Written atomically (temporary file, fsync, rename, fsync of
// the directory). A truncated or corrupted file is refused with an error naming the file, the offset and
// the field; nothing is half-loaded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/common/result.hpp"

namespace ogf::filter {

// 2 added freeClampZ, 3 the occupied priority and the cell marks; versions 1 and 2 are read too (their
// cells carry no marks).
inline constexpr std::uint32_t kMapFileVersion = 3;
// Layout of version 3: header fields [0, 136) ending with the payload checksum at [128, 136), the header
// checksum (over [0, 136)) at [136, 144), blocks from 144 on. Version 2 lacks the occupied priority and
// release count ([96, 104), after the free clamp at [88, 96)), version 1 also the free clamp (after the
// clamp at [80, 88)), so their offsets are 8 and 16 less.
inline constexpr std::size_t kMapFilePayloadChecksumAt = 128;
inline constexpr std::size_t kMapFileHeaderChecksumAt = 136;
inline constexpr std::size_t kMapFilePayloadAt = 144;

std::vector<std::uint8_t> encodeMap(const BandedOgf& map);
// The bytes encodeMap writes for a map with `map`'s storage holding `cells` allocated cells (whole blocks):
// the header, then for each block its key, its floats and a mark per cell (with banded covariance 57 bytes
// a cell, with compact 9).
std::uint64_t encodedMapBytes(const BandedOgf& map, std::uint64_t cells);
// `source` names the bytes in error messages (a path, or "<memory>"). `threads` is a runtime setting the
// file does not carry.
Result<BandedOgf> decodeMap(std::span<const std::uint8_t> bytes, std::string_view source = "<memory>",
                            int threads = 1);

Status saveMapFile(const BandedOgf& map, const std::filesystem::path& path);
Result<BandedOgf> loadMapFile(const std::filesystem::path& path, int threads = 1);

}  // namespace ogf::filter
