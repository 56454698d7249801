// Writes an Image as a PNG file (8-bit grey or RGB, no interlace): signature, IHDR, one IDAT holding a zlib
// stream of the deflated scanlines (zlib_stream.hpp), IEND, each chunk with its CRC-32.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ogf/tools/image.hpp"

namespace ogf::tools {

// The PNG file's bytes.
std::vector<std::uint8_t> encodePng(const Image& image);

// Writes the file; on failure returns false and sets `error` (naming the path).
bool writePng(const std::filesystem::path& path, const Image& image, std::string& error);

}  // namespace ogf::tools
