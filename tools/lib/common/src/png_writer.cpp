// PNG chunks around a deflated zlib stream of filter-0 scanlines.
#include "ogf/tools/png_writer.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include <ogf/common/crc32.hpp>

#include "ogf/tools/zlib_stream.hpp"

namespace ogf::tools {
namespace {

void putBigEndian32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) {
    out.push_back(static_cast<std::uint8_t>((v >> shift) & 0xFFU));
  }
}

void putChunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::vector<std::uint8_t>& data) {
  putBigEndian32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t typeAt = out.size();
  for (int i = 0; i < 4; ++i) {
    out.push_back(static_cast<std::uint8_t>(type[i]));
  }
  out.insert(out.end(), data.begin(), data.end());
  // The CRC covers the chunk type and data, not the length.
  putBigEndian32(out, ogf::crc32(out.data() + typeAt, 4 + data.size()));
}

}  // namespace

std::vector<std::uint8_t> encodePng(const Image& image) {
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  std::vector<std::uint8_t> header;
  putBigEndian32(header, static_cast<std::uint32_t>(image.width));
  putBigEndian32(header, static_cast<std::uint32_t>(image.height));
  header.push_back(8);                                          // bit depth
  header.push_back(image.channels == 1 ? 0 : 2);                // colour type: grey or truecolour
  header.push_back(0);                                          // deflate
  header.push_back(0);                                          // adaptive filtering
  header.push_back(0);                                          // no interlace
  putChunk(out, "IHDR", header);

  const auto rowBytes = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.channels);
  std::vector<std::uint8_t> raw;
  raw.reserve((rowBytes + 1) * static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);  // filter type None
    const auto begin = image.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * rowBytes);
    raw.insert(raw.end(), begin, begin + static_cast<std::ptrdiff_t>(rowBytes));
  }
  putChunk(out, "IDAT", zlibDeflate(raw));
  putChunk(out, "IEND", {});
  return out;
}

bool writePng(const std::filesystem::path& path, const Image& image, std::string& error) {
  const std::vector<std::uint8_t> bytes = encodePng(image);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    error = path.string() + ": cannot open for writing: " + std::strerror(errno);
    return false;
  }
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!file) {
    error = path.string() + ": write failed";
    return false;
  }
  return true;
}

}  // namespace ogf::tools
