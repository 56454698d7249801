// Where tests find ../shared (real captures, calibrations, SLAM logs). Tests that need it skip with a
// clear message when it is absent; nothing from it is ever copied into the repository.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace ogf::testing {

// $OGF_SHARED_DIR (set by ctest to <source>/../shared), else ../shared from the working directory.
std::filesystem::path sharedDir();

// The file at `relative` under sharedDir(), or nullopt when it does not exist.
std::optional<std::filesystem::path> sharedFile(const std::string& relative);

}  // namespace ogf::testing

// Skips the current test with the path it looked for when a shared file is absent.
#define OGF_REQUIRE_SHARED_FILE(var, relative)                                                   \
  const auto var##_opt = ::ogf::testing::sharedFile(relative);                                     \
  if (!var##_opt) GTEST_SKIP() << "shared data absent: " << (::ogf::testing::sharedDir() / relative) \
                               << " (tests read ../shared beside the checkout)";                   \
  const std::filesystem::path var = *var##_opt
