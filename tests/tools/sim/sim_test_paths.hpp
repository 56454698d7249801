// Scratch paths for the ogf_sim tests, unique per process so suites run from several build trees (or
// ctest -j) at once never share a file.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

namespace ogf::sim::test {

inline std::filesystem::path scratchPath(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("ogf_sim_test_" + std::to_string(::getpid()) + "_" + name);
}

}  // namespace ogf::sim::test
