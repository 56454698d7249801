#include "ogf/map_io/lcm_log_scans.hpp"

#include <lcm/lcm-cpp.hpp>

#include <fmt/format.h>

#include <cstdio>

#include "ogf/messages/decode_message.hpp"

namespace ogf::map_io {

Result<LcmLogScanCounts> readLcmLogScans(const std::filesystem::path& path, const std::string& channel,
                                         const std::function<void(const ScanRecord&)>& visit,
                                         const std::function<void(double)>& progress) {
  std::error_code ec;
  const auto file_size = std::filesystem::file_size(path, ec);
  if (ec) return Error{fmt::format("{}: {}", path.string(), ec.message())};
  lcm::LogFile log(path.string(), "r");
  if (!log.good()) return Error{fmt::format("{}: cannot open as an LCM log", path.string())};
  LcmLogScanCounts counts;
  ogf::lidar_scan_t message;
  ScanRecord record;
  while (const lcm::LogEvent* event = log.readNextEvent()) {
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
    ++counts.scans;
    visit(record);
    if (progress && file_size > 0) {
      const long pos = std::ftell(log.getFilePtr());
      if (pos >= 0) progress(static_cast<double>(pos) / static_cast<double>(file_size));
    }
  }
  return counts;
}

}  // namespace ogf::map_io
