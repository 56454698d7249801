// The pose CSV: see pose_csv.hpp.
#include "ogf/tools/pose_csv.hpp"

#include "ogf/tools/csv_reader.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <system_error>

namespace ogf::tools {
namespace {

constexpr std::size_t kMaxProblems = 50;
constexpr std::array<const char*, 8> kColumns = {"utime", "x", "y", "z", "qw", "qx", "qy", "qz"};

template <class T>
bool parseNumber(std::string_view field, T& value) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  return ec == std::errc() && ptr == end && !field.empty();
}

// One data row's fields into a pose row, or why not (empty when it parsed).
std::string parseRow(const std::vector<std::string>& fields, PoseCsvRow& row) {
  if (fields.size() > kColumns.size()) return "more than 8 fields (expected utime,x,y,z,qw,qx,qy,qz)";
  if (fields.size() != kColumns.size()) {
    return std::to_string(fields.size()) + " fields, expected 8 (utime,x,y,z,qw,qx,qy,qz)";
  }
  if (!parseNumber(fields[0], row.utime)) {
    return "utime '" + fields[0] + "' is not an integer (microseconds)";
  }
  for (std::size_t i = 0; i < row.values.size(); ++i) {
    if (!parseNumber(fields[i + 1], row.values[i]) || !std::isfinite(row.values[i])) {
      return std::string(kColumns[i + 1]) + " '" + fields[i + 1] + "' is not a finite number";
    }
  }
  return {};
}

}  // namespace

PoseCsv parsePoseCsv(std::string_view text, std::string_view source) {
  PoseCsv out;
  // csv_reader has dropped blank lines and comments and trimmed the fields.
  std::vector<CsvRow> lines = parseCsv(text);
  const bool header = !lines.empty() && lines.front().fields.front().substr(0, 5) == "utime";
  for (std::size_t i = header ? 1 : 0; i < lines.size(); ++i) {
    PoseCsvRow row;
    row.line = lines[i].line;
    if (const std::string why = parseRow(lines[i].fields, row); !why.empty()) {
      ++out.skipped;
      if (out.problems.size() < kMaxProblems) {
        out.problems.push_back(std::string(source) + ":" + std::to_string(row.line) + ": " + why + "; line skipped");
      }
      continue;
    }
    out.rows.push_back(row);
  }
  return out;
}

std::string formatPoseCsvRow(std::int64_t utime, const std::array<double, 7>& v) {
  // "+ 0.0" turns -0.0 into 0.0, so a level pose reads 0 rather than -0.
  return fmt::format("{},{:.6f},{:.6f},{:.6f},{:.9f},{:.9f},{:.9f},{:.9f}", utime, v[0] + 0.0, v[1] + 0.0, v[2] + 0.0,
                     v[3] + 0.0, v[4] + 0.0, v[5] + 0.0, v[6] + 0.0);
}

}  // namespace ogf::tools
