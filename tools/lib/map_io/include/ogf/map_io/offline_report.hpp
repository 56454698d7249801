// The lines ogf-map says about a run: a scan the odometry does not cover, and the closing line on stdout
//   scans <mapped> measurements <cell measurements> cells <allocated cells> seconds <wall time> checksum
//   <hex>
// that scripts and the tests read.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/scan_record.hpp"

namespace ogf::map_io {

// "scan 7 at utime ... (host time) is not covered by the odometry of odo.csv (utime a .. b); left out";
// `span` is the odometry's (nullopt: "no poses").
std::string uncoveredScanNote(const ScanRecord& scan, TimeBase base, const std::string& odometry_source,
                              const std::optional<std::pair<std::int64_t, std::int64_t>>& span);

// The closing line, without its newline; the checksum is the filter's (filter::BandedOgf::checksum).
std::string mapSummaryLine(const OfflineCounts& counts, const filter::BandedOgf& map, double seconds);

}  // namespace ogf::map_io
