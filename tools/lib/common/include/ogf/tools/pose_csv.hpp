// The pose CSV the tools exchange (ogf-sim writes it, ogf-replay publishes it, ogf-map and ogf-eval read it):
// a header line `utime,x,y,z,qw,qx,qy,qz`, then one pose per line: µs since the epoch, position in metres,
// orientation as a quaternion w, x, y, z. One parser and one row format for all of them, so the tools
// agree on what a well-formed line is and name a bad one the same way.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ogf::tools {

inline constexpr const char* kPoseCsvHeader = "utime,x,y,z,qw,qx,qy,qz";

struct PoseCsvRow {
  int line = 0;                   // 1-based
  std::int64_t utime = 0;         // µs
  std::array<double, 7> values{};  // x, y, z, qw, qx, qy, qz, all finite
};

struct PoseCsv {
  std::vector<PoseCsvRow> rows;       // in file order
  std::int64_t skipped = 0;           // malformed lines (exact)
  std::vector<std::string> problems;  // the first 50 of them: "<source>:<line>: <why>; line skipped"
};

// Blank lines and lines starting with '#' are ignored, and the first other line when it starts with
// "utime" (the header, whatever its spacing). Fields may carry spaces around them. A line is malformed
// when it has not 8 fields, its utime is not an integer or a value is not a finite number; the message
// names the field and its text.
PoseCsv parsePoseCsv(std::string_view text, std::string_view source);

// One data line (no newline): utime, position with 6 decimals, quaternion with 9; -0 written as 0.
std::string formatPoseCsvRow(std::int64_t utime, const std::array<double, 7>& values);

}  // namespace ogf::tools
