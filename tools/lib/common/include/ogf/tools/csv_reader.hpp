// Reads a comma-separated file into rows of trimmed text fields (no quoting), skipping blank lines and lines
// starting with '#'. Each row remembers its line number for error messages.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ogf::tools {

struct CsvRow {
  int line = 0;  // 1-based
  std::vector<std::string> fields;
};

bool readCsv(const std::filesystem::path& path, std::vector<CsvRow>& rows, std::string& error);
// The same from text already in memory.
std::vector<CsvRow> parseCsv(std::string_view text);

}  // namespace ogf::tools
