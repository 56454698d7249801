// Test helper: the value printed after a key in a program's output line ("key value"), as ogf-map-client
// and the other programs print their summaries.
#pragma once

#include <regex>
#include <string>

namespace ogf::testing {

// The first whitespace-free word after `key` and one space in `line`; empty when `key` is not there.
inline std::string outputField(const std::string& line, const std::string& key) {
  std::smatch m;
  if (std::regex_search(line, m, std::regex(key + " (\\S+)"))) return m[1];
  return {};
}

}  // namespace ogf::testing
