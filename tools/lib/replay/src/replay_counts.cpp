// The replay's counts and its summary line: see replay_counts.hpp.
#include "ogf/replay/replay_counts.hpp"

#include <cstdio>

namespace ogf::replay {

std::string summaryLine(const ReplayCounts& counts, int loops, double seconds) {
  const double rate = seconds > 0 ? static_cast<double>(counts.packets()) / seconds : 0.0;
  char line[512];
  std::snprintf(line, sizeof line,
                "packets %lld data %lld position %lld other %lld skipped %lld send_errors %lld poses %lld loops %d "
                "seconds %.3f rate %.1f\n",
                static_cast<long long>(counts.packets()), static_cast<long long>(counts.data),
                static_cast<long long>(counts.position), static_cast<long long>(counts.other),
                static_cast<long long>(counts.skipped), static_cast<long long>(counts.send_errors),
                static_cast<long long>(counts.poses), loops, seconds, rate);
  return line;
}

}  // namespace ogf::replay
