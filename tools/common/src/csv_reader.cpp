// Line by line, split at commas, trim spaces and a trailing CR.
#include "ogf/tools/csv_reader.hpp"

#include <fstream>

namespace ogf::tools {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) {
    return {};
  }
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

}  // namespace

bool readCsv(const std::filesystem::path& path, std::vector<CsvRow>& rows, std::string& error) {
  std::ifstream file(path);
  if (!file) {
    error = path.string() + ": cannot open";
    return false;
  }
  std::string line;
  int number = 0;
  while (std::getline(file, line)) {
    ++number;
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') {
      continue;
    }
    CsvRow row;
    row.line = number;
    std::size_t start = 0;
    for (;;) {
      const auto comma = t.find(',', start);
      row.fields.push_back(trim(t.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
      if (comma == std::string::npos) {
        break;
      }
      start = comma + 1;
    }
    rows.push_back(std::move(row));
  }
  return true;
}

}  // namespace ogf::tools
