// Test helper: the whole content of a file, as text (empty when it cannot be read: a test then fails on
// what it expected to find there).
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace ogf::testing {

inline std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace ogf::testing
