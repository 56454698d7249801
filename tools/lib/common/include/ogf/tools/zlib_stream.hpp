// A zlib stream (RFC 1950) of deflated data (RFC 1951), made by Debian's zlib, with its Adler-32 check
// value. Used for PNG image data: a figure of flat colours shrinks about a hundredfold.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::tools {

std::uint32_t adler32(std::span<const std::uint8_t> bytes);

// `data` deflated (zlib's default level) and wrapped as a zlib stream.
std::vector<std::uint8_t> zlibDeflate(std::span<const std::uint8_t> data);

}  // namespace ogf::tools
