// A zlib stream through zlib's compress2 (header, deflate blocks, Adler-32 trailer).
#include "ogf/tools/zlib_stream.hpp"

#include <zlib.h>

#include <stdexcept>

namespace ogf::tools {

std::uint32_t adler32(std::span<const std::uint8_t> bytes) {
  uLong a = ::adler32(0L, Z_NULL, 0);
  return static_cast<std::uint32_t>(::adler32_z(a, bytes.data(), bytes.size()));
}

std::vector<std::uint8_t> zlibDeflate(std::span<const std::uint8_t> data) {
  uLongf size = ::compressBound(static_cast<uLong>(data.size()));
  std::vector<std::uint8_t> out(size);
  if (::compress2(out.data(), &size, data.data(), static_cast<uLong>(data.size()), Z_DEFAULT_COMPRESSION) != Z_OK) {
    throw std::runtime_error("zlib compress2 failed");  // only on exhausted memory
  }
  out.resize(size);
  return out;
}

}  // namespace ogf::tools
