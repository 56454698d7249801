// Line by line, split at commas, trim spaces and a trailing CR.
#include "ogf/tools/csv_reader.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

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

std::vector<CsvRow> parseCsv(std::string_view text) {
  std::vector<CsvRow> rows;
  int number = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string t = trim(std::string(text.substr(0, nl)));
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++number;
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
  return rows;
}

bool readCsv(const std::filesystem::path& path, std::vector<CsvRow>& rows, std::string& error) {
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    error = path.string() + ": cannot open";
    return false;
  }
  std::ostringstream text;
  text << file.rdbuf();
  std::vector<CsvRow> parsed = parseCsv(text.str());
  rows.insert(rows.end(), std::make_move_iterator(parsed.begin()), std::make_move_iterator(parsed.end()));
  return true;
}

}  // namespace ogf::tools
