#include "ogf/map_io/offline_report.hpp"

#include <fmt/format.h>

namespace ogf::map_io {

std::string uncoveredScanNote(const ScanRecord& scan, TimeBase base, const std::string& odometry_source,
                              const std::optional<std::pair<std::int64_t, std::int64_t>>& span) {
  return fmt::format(
      "scan {} at utime {} ({} time) is not covered by the odometry of {} ({}); left out", scan.seq,
      scan.points(base).start_utime, fusion::clockName(scan.clock(base)), odometry_source,
      span ? fmt::format("utime {} .. {}", span->first, span->second) : std::string("no poses"));
}

std::string mapSummaryLine(const OfflineCounts& counts, const filter::BandedOgf& map, double seconds) {
  return fmt::format("scans {} measurements {} cells {} seconds {:.2f} checksum {:016x}", counts.scans_mapped,
                     counts.measurements, map.allocatedCells(), seconds, map.checksum());
}

}  // namespace ogf::map_io
