// A zlib stream (RFC 1950) of stored (uncompressed) deflate blocks (RFC 1951 §3.2.4) with its Adler-32:
// valid input for any inflater, no compression library needed. Used for PNG image data.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::tools {

std::uint32_t adler32(std::span<const std::uint8_t> bytes);

// `data` wrapped as a zlib stream.
std::vector<std::uint8_t> zlibStored(std::span<const std::uint8_t> data);

}  // namespace ogf::tools
