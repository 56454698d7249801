// Which source's scan the worker maps next when several sources have one ready: a deficit by source, counted
// in the worker's time. Of the ready sources, those whose time on the worker is within `slack` of the least
// served one's are eligible, and of them the scan that began first goes next. While the worker keeps up (or
// the sources take alike) this is oldest-first across sources, as one clock would order them; a source that
// takes more than its share (forged scans dated in the past, scans larger or faster than the worker maps)
// is served only with the time the others leave, so what it sends beyond that waits in its own queue and is
// dropped from there, never from another source's. Credit is bounded: no source counts more than `window`
// behind the most served, so a source silent for long does not then hold the worker for as long.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ogf::fusion {

class FairShare {
 public:
  struct Candidate {
    std::size_t source;        // 0 .. sources - 1
    std::int64_t begin_utime;  // when its ready scan began
  };

  // `slack_us` and `window_us` must be positive and slack within window.
  FairShare(std::size_t sources, std::int64_t slack_us, std::int64_t window_us);

  // The candidate to map next (an index into `ready`), nothing when `ready` is empty.
  std::optional<std::size_t> choose(std::span<const Candidate> ready) const;
  // The worker spent `us` on a scan of `source`.
  void served(std::size_t source, std::int64_t us);
  // The worker's time counted for `source`, as choose() sees it.
  std::int64_t servedUs(std::size_t source) const;

 private:
  std::vector<std::int64_t> served_us_;
  std::int64_t slack_us_;
  std::int64_t window_us_;
};

}  // namespace ogf::fusion
