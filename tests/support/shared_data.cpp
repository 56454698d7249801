#include "support/shared_data.hpp"

#include <cstdlib>

namespace ogf::testing {

std::filesystem::path sharedDir() {
  if (const char* env = std::getenv("OGF_SHARED_DIR"); env != nullptr && *env != '\0') return env;
  return std::filesystem::path("..") / "shared";
}

std::optional<std::filesystem::path> sharedFile(const std::string& relative) {
  auto p = sharedDir() / relative;
  std::error_code ec;
  if (std::filesystem::exists(p, ec)) return p;
  return std::nullopt;
}

}  // namespace ogf::testing
