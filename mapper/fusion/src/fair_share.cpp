#include "ogf/fusion/fair_share.hpp"

#include <algorithm>

namespace ogf::fusion {

FairShare::FairShare(std::size_t sources, std::int64_t slack_us, std::int64_t window_us)
    : served_us_(sources, 0), slack_us_(slack_us), window_us_(window_us) {}

std::optional<std::size_t> FairShare::choose(std::span<const Candidate> ready) const {
  if (ready.empty()) return std::nullopt;
  std::int64_t least = servedUs(ready.front().source);
  for (const Candidate& c : ready) least = std::min(least, servedUs(c.source));
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < ready.size(); ++i) {
    if (servedUs(ready[i].source) > least + slack_us_) continue;
    if (!best || ready[i].begin_utime < ready[*best].begin_utime) best = i;
  }
  return best;
}

void FairShare::served(std::size_t source, std::int64_t us) {
  served_us_.at(source) += std::max<std::int64_t>(us, 0);
  // The credit bound: everyone at least `window` behind the most served.
  const std::int64_t floor = *std::max_element(served_us_.begin(), served_us_.end()) - window_us_;
  for (std::int64_t& s : served_us_) s = std::max(s, floor);
}

std::int64_t FairShare::servedUs(std::size_t source) const { return served_us_.at(source); }

}  // namespace ogf::fusion
