// PGM header tokens, then binary (1 or 2 bytes big-endian per value) or ASCII values.
#include "ogf/tools/pgm_reader.hpp"

#include <cctype>
#include <fstream>
#include <iterator>

namespace ogf::tools {
namespace {

// Next whitespace-separated token of the header, skipping '#' comments.
bool nextToken(const std::string& text, std::size_t& pos, std::string& token) {
  token.clear();
  while (pos < text.size()) {
    const auto c = static_cast<unsigned char>(text[pos]);
    if (c == '#') {
      while (pos < text.size() && text[pos] != '\n') {
        ++pos;
      }
    } else if (std::isspace(c) != 0) {
      ++pos;
    } else {
      break;
    }
  }
  while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos])) == 0) {
    token.push_back(text[pos++]);
  }
  return !token.empty();
}

bool parseInt(const std::string& token, int& value) {
  if (token.empty() || token.size() > 6) {
    return false;
  }
  value = 0;
  for (char c : token) {
    if (c < '0' || c > '9') {
      return false;
    }
    value = value * 10 + (c - '0');
  }
  return true;
}

}  // namespace

bool readPgm(const std::filesystem::path& path, Greymap& out, std::string& error) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    error = path.string() + ": cannot open";
    return false;
  }
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  std::string magic;
  std::string w;
  std::string h;
  std::string m;
  if (!nextToken(text, pos, magic) || (magic != "P5" && magic != "P2")) {
    error = path.string() + ": not a PGM file (magic must be P5 or P2)";
    return false;
  }
  if (!nextToken(text, pos, w) || !nextToken(text, pos, h) || !nextToken(text, pos, m) ||
      !parseInt(w, out.width) || !parseInt(h, out.height) || !parseInt(m, out.maxValue) || out.width <= 0 ||
      out.height <= 0 || out.maxValue <= 0 || out.maxValue > 65535) {
    error = path.string() + ": bad PGM header (width, height, maxval)";
    return false;
  }
  const auto count = static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height);
  out.values.assign(count, 0);
  if (magic == "P5") {
    ++pos;  // the single whitespace after maxval
    const std::size_t bytesPer = out.maxValue > 255 ? 2 : 1;
    if (text.size() < pos + count * bytesPer) {
      error = path.string() + ": truncated: " + std::to_string(count) + " values expected";
      return false;
    }
    for (std::size_t i = 0; i < count; ++i) {
      const auto hi = static_cast<unsigned char>(text[pos + i * bytesPer]);
      out.values[i] = bytesPer == 1 ? hi
                                    : static_cast<std::uint16_t>(
                                          (hi << 8) | static_cast<unsigned char>(text[pos + i * bytesPer + 1]));
    }
    return true;
  }
  std::string token;
  for (std::size_t i = 0; i < count; ++i) {
    int v = 0;
    if (!nextToken(text, pos, token) || !parseInt(token, v) || v > out.maxValue) {
      error = path.string() + ": value " + std::to_string(i) + " missing or out of range";
      return false;
    }
    out.values[i] = static_cast<std::uint16_t>(v);
  }
  return true;
}

}  // namespace ogf::tools
