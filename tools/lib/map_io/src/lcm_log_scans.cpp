#include "ogf/map_io/lcm_log_scans.hpp"

#include <lcm/lcm-cpp.hpp>

#include <fmt/format.h>

#include <cstdio>

#include "ogf/log_io/log_events.hpp"
#include "ogf/log_io/stream_gaps.hpp"
#include "ogf/messages/decode_message.hpp"

namespace ogf::map_io {

Result<LcmLogScanCounts> readLcmLogScans(const std::filesystem::path& path, const std::string& channel,
                                         const std::function<void(const ScanRecord&)>& visit,
                                         const std::function<void(double)>& progress) {
  auto log = log_io::LogEvents::open(path);
  if (!log) return log.error();
  LcmLogScanCounts counts;
  log_io::StreamGaps gaps;
  ogf::lidar_scan_t message;
  ScanRecord record;
  while (const lcm::LogEvent* event = log->next()) {
    ++counts.events;
    if (event->channel != channel) continue;
    if (auto why = ogf::messages::decodeMessage(event->data, static_cast<std::size_t>(event->datalen), message)) {
      ++counts.skipped;
      if (counts.problems.size() < 20)
        counts.problems.push_back(fmt::format("{}: event {} on {}: not an ogf.lidar_scan_t that decodes ({}); skipped",
                                              path.string(), event->eventnum, channel, *why));
      continue;
    }
    assignScan(message, record);
    gaps.add(message.utime, message.seq);
    ++counts.scans;
    visit(record);
    if (progress) progress(log->fractionRead());
  }
  counts.gaps = gaps.summary(path.string() + ": " + channel);
  return counts;
}

}  // namespace ogf::map_io
