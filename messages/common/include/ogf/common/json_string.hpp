// A text as a JSON string literal (RFC 8259 section 7): quotes and backslashes escaped, control characters
// as \uXXXX, everything else as it is (UTF-8 passes through).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

namespace ogf {

inline std::string jsonString(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace ogf
