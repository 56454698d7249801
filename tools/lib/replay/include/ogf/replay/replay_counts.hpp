// What a replay sent, skipped and missed, and the one line ogf-replay prints on stdout at the end:
//   packets N data N position N other N skipped N send_errors N poses N loops N seconds S rate R
// (scripts and tests read it, so its fields and their order are fixed).
#pragma once

#include <cstdint>
#include <string>

namespace ogf::replay {

struct ReplayCounts {
  std::int64_t data = 0;
  std::int64_t position = 0;
  std::int64_t other = 0;
  std::int64_t skipped = 0;      // records that are not a whole IPv4/UDP datagram
  std::int64_t send_errors = 0;  // sendto failures (counted, the replay goes on)
  std::int64_t poses = 0;
  std::int64_t pose_errors = 0;
  std::int64_t late_us_max = 0;  // worst lateness of a send behind its due time
  std::int64_t packets() const { return data + position + other; }
};

// The summary line, newline included; `rate` is packets per second over `seconds` (0 when no time passed).
std::string summaryLine(const ReplayCounts& counts, int loops, double seconds);

}  // namespace ogf::replay
