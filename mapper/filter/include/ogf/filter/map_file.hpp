// The banded map on disk. A header (magic, version, dimensions, resolution, kernel σ and amplitude, stencil
// R and L, taper support, thresholds, skip tolerance and clamps, block layout, block count), a 64-bit checksum of the payload and one
// of the header, then every block (key, then its floats) in key order; all little-endian. Written
// atomically (temporary file, fsync, rename, fsync of the directory). A truncated or corrupted file is
// refused with an error naming the file, the offset and the field; nothing is half-loaded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "ogf/filter/banded_ogf.hpp"
#include "ogf/filter/result.hpp"

namespace ogf::filter {

inline constexpr std::uint32_t kMapFileVersion = 2;  // 2 added freeClampZ; version 1 files are read too
// Layout of version 2: header fields [0, 128) ending with the payload checksum at [120, 128), the header
// checksum (over [0, 128)) at [128, 136), blocks from 136 on. Version 1 lacks the free clamp (8 bytes after
// the clamp at [80, 88)), so its offsets are 8 less.
inline constexpr std::size_t kMapFilePayloadChecksumAt = 120;
inline constexpr std::size_t kMapFileHeaderChecksumAt = 128;
inline constexpr std::size_t kMapFilePayloadAt = 136;

std::vector<std::uint8_t> encodeMap(const BandedOgf& map);
// `source` names the bytes in error messages (a path, or "<memory>"). `threads` is a runtime setting the
// file does not carry.
Result<BandedOgf> decodeMap(std::span<const std::uint8_t> bytes, std::string_view source = "<memory>",
                            int threads = 1);

Status saveMapFile(const BandedOgf& map, const std::filesystem::path& path);
Result<BandedOgf> loadMapFile(const std::filesystem::path& path, int threads = 1);

}  // namespace ogf::filter
