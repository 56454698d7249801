#include "support/test_directory.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

namespace ogf::testing {

std::filesystem::path emptyTestDirectory(const std::string& prefix) {
  std::string name = prefix + "-" + std::to_string(::getpid());
  if (const auto* test = ::testing::UnitTest::GetInstance()->current_test_info()) {
    name += "-" + std::string(test->name());
  }
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ogf::testing
