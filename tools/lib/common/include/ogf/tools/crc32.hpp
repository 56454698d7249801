// CRC-32 (ISO-HDLC, polynomial 0xEDB88320 reflected), the checksum of PNG chunks and of gzip.
#pragma once

#include <cstdint>
#include <span>

namespace ogf::tools {

// CRC of `bytes`, continuing from `crc` (0 to start).
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace ogf::tools
