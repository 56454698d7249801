// Reads a PGM (Netpbm greymap) file, binary P5 or plain P2, comments allowed in the header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ogf::tools {

struct Greymap {
  int width = 0;
  int height = 0;
  int maxValue = 255;
  std::vector<std::uint16_t> values;  // row-major, top row first
  std::uint16_t at(int row, int col) const {
    return values[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col)];
  }
};

// False with `error` naming the file and what was wrong.
bool readPgm(const std::filesystem::path& path, Greymap& out, std::string& error);

}  // namespace ogf::tools
