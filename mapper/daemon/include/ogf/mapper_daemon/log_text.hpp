// Text that arrives from the bus (a requester's name, an export file name) made safe for one log line and
// the status: control characters (a newline would start a forged log line) and bytes beyond ASCII become
// '?', and it is cut to `max` characters, a cut marked by "...".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace ogf::mapper_daemon {

inline constexpr std::size_t kMaxLoggedName = 64;

inline std::string sanitisedForLog(std::string_view text, std::size_t max = kMaxLoggedName) {
  std::string out;
  const bool cut = text.size() > max;
  const std::size_t keep = cut ? (max > 3 ? max - 3 : 0) : text.size();
  out.reserve(keep + 3);
  for (std::size_t i = 0; i < keep; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out.push_back(c < 0x20 || c >= 0x7f ? '?' : static_cast<char>(c));
  }
  if (cut) out += "...";
  return out;
}

}  // namespace ogf::mapper_daemon
