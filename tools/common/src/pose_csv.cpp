// The pose CSV: see pose_csv.hpp.
#include "ogf/tools/pose_csv.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <system_error>

namespace ogf::tools {
namespace {

constexpr std::size_t kMaxProblems = 50;
constexpr std::array<const char*, 8> kColumns = {"utime", "x", "y", "z", "qw", "qx", "qy", "qz"};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

template <class T>
bool parseNumber(std::string_view field, T& value) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  const char* end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  return ec == std::errc() && ptr == end && !field.empty();
}

// One data line into a row, or why not (empty when it parsed).
std::string parseRow(std::string_view line, PoseCsvRow& row) {
  std::array<std::string_view, 8> fields;
  std::size_t n = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    if (n == fields.size()) return "more than 8 fields (expected utime,x,y,z,qw,qx,qy,qz)";
    fields[n++] = trim(line.substr(0, comma));
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  if (n != fields.size()) return std::to_string(n) + " fields, expected 8 (utime,x,y,z,qw,qx,qy,qz)";
  if (!parseNumber(fields[0], row.utime)) {
    return "utime '" + std::string(fields[0]) + "' is not an integer (microseconds)";
  }
  for (std::size_t i = 0; i < row.values.size(); ++i) {
    if (!parseNumber(fields[i + 1], row.values[i]) || !std::isfinite(row.values[i])) {
      return std::string(kColumns[i + 1]) + " '" + std::string(fields[i + 1]) + "' is not a finite number";
    }
  }
  return {};
}

}  // namespace

PoseCsv parsePoseCsv(std::string_view text, std::string_view source) {
  PoseCsv out;
  int lineNo = 0;
  bool seenFirst = false;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    const std::string_view line = trim(text.substr(0, nl));
    text = nl == std::string_view::npos ? std::string_view{} : text.substr(nl + 1);
    ++lineNo;
    if (line.empty() || line.front() == '#') continue;
    if (!seenFirst) {
      seenFirst = true;
      if (line.substr(0, 5) == "utime") continue;
    }
    PoseCsvRow row;
    row.line = lineNo;
    if (const std::string why = parseRow(line, row); !why.empty()) {
      ++out.skipped;
      if (out.problems.size() < kMaxProblems) {
        out.problems.push_back(std::string(source) + ":" + std::to_string(lineNo) + ": " + why + "; line skipped");
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
