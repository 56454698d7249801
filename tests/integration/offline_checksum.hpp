// The map the mapping daemon must hold after the scan feeder's scans 0..n-1, computed offline: the same
// scans and odometry through a ScanMapper with the daemon's default configuration. A test compares the
// daemon's OGF_MAPPER_STATUS filter_checksum with it, whatever else (restarts, bad input) happened.
#pragma once

#include <cstdint>

namespace ogf::testing {

// The filter checksum after mapping feedStep(0..n-1, points); 0 if a scan was not covered by its odometry.
std::uint64_t offlineChecksum(int n, int points = 1500);

}  // namespace ogf::testing
