// Test helper: ogf-map's summary line ("scans N measurements N cells N seconds S checksum X") without its
// wall time, so two runs that made the same map compare equal; "" when the output holds no such line.
#pragma once

#include <regex>
#include <string>

namespace ogf::testing {

inline std::string mapSummary(const std::string& stdout_text) {
  std::smatch m;
  static const std::regex re(R"(scans (\d+) measurements (\d+) cells (\d+) seconds [0-9.]+ checksum ([0-9a-f]+))");
  if (!std::regex_search(stdout_text, m, re)) return "";
  return "scans " + m[1].str() + " measurements " + m[2].str() + " cells " + m[3].str() + " checksum " + m[4].str();
}

}  // namespace ogf::testing
