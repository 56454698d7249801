// The compressions of MCAP chunks (MCAP registry, "Compression formats"): none (""), "zstd" (a Zstandard
// frame, Debian's libzstd) and "lz4" (an LZ4 frame, Debian's liblz4), and the CRC-32 chunks and sections
// carry (the IEEE polynomial of zlib's crc32). Decompression writes at most the size the chunk declares and
// fails when the data would make more or less, so a damaged or hostile chunk never makes it allocate more
// than the caller's bound.
#pragma once

#include <cstdint>
#include <ogf/common/result.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ogf::mcap {

bool isKnownCompression(std::string_view compression);

// `records` decompressed to exactly `uncompressed_size` bytes (the caller bounds that size).
Result<std::vector<std::uint8_t>> decompressRecords(std::string_view compression,
                                                    std::span<const std::uint8_t> records,
                                                    std::uint64_t uncompressed_size);

// `records` compressed with "zstd" (at `level`) or "lz4"; "" returns them as they are.
Result<std::vector<std::uint8_t>> compressRecords(std::string_view compression,
                                                  std::span<const std::uint8_t> records, int level = 3);

// CRC-32 of `bytes` continuing from `crc` (0 to start).
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace ogf::mcap
