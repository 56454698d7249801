// The gaps of one recorded stream (a channel of an LCM log): messages missing between sequence numbers
// when the stream has them, else silences much longer than the stream's usual interval. Pure: times and
// sequence numbers come in as arguments.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace ogf::log_io {

class StreamGaps {
 public:
  // One message at `utime` (microseconds), with its sequence number when the stream numbers them.
  void add(std::int64_t utime, std::optional<std::int64_t> seq = std::nullopt);

  std::int64_t messages() const { return messages_; }
  int gaps() const { return gaps_; }
  // Messages missing: exact from sequence numbers, else estimated from each silence / the usual interval.
  std::int64_t missing() const { return missing_; }
  std::int64_t longestGapUs() const { return longest_us_; }

  // "<what>: N missing in G gaps (the longest X s) out of M + N" or "" when there is none.
  std::string summary(const std::string& what) const;

 private:
  std::int64_t messages_ = 0;
  std::int64_t missing_ = 0;
  int gaps_ = 0;
  std::int64_t longest_us_ = 0;
  std::optional<std::int64_t> last_utime_;
  std::optional<std::int64_t> last_seq_;
  double usual_interval_us_ = 0;  // running mean of the intervals that were not gaps
  std::int64_t intervals_ = 0;
};

}  // namespace ogf::log_io
