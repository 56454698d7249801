// The scans of an LCM log as lcm-logger records them: every ogf.lidar_scan_t on the scan channel
// (VELODYNE_SCAN), in log order, handed to a visitor one at a time so a long drive never sits in memory.
// A record with another fingerprint or one that does not decode is skipped and counted; scans missing
// between sequence numbers are reported.
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "ogf/map_io/scan_record.hpp"

namespace ogf::map_io {

struct LcmLogScanCounts {
  std::int64_t events = 0;   // every event in the log
  std::int64_t scans = 0;    // decoded and visited
  std::int64_t skipped = 0;  // on the scan channel but not a lidar_scan_t that decodes
  std::vector<std::string> problems;  // the first few, naming file and event number
  std::string gaps;  // scans missing between sequence numbers ("" when none)
};

// `progress` (optional) receives the fraction of the file read after each scan.
Result<LcmLogScanCounts> readLcmLogScans(const std::filesystem::path& path, const std::string& channel,
                                         const std::function<void(const ScanRecord&)>& visit,
                                         const std::function<void(double)>& progress = {});

}  // namespace ogf::map_io
