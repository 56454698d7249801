// The map the mapping daemon must hold after the scan feeder's scans 0..n-1, computed offline: the same
// scans and odometry through a ScanMapper with the daemon's default configuration. A test compares the
// daemon's OGF_MAPPER_STATUS filter_checksum with it, whatever else (restarts, bad input) happened.
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "scan_feeder.hpp"

namespace ogf::testing {

// The filter checksum after mapping feedStep(0..n-1, points); 0 if a scan was not covered by its odometry.
std::uint64_t offlineChecksum(int n, int points = 1500);

// The filter checksum after mapping `steps` as given (their odometry may be edited), leaving out the scans
// of the steps in `skip` (their odometry still counts) and the scans spanning a split of the trajectory;
// `broken` (when given) receives how many scans spanned one. 0 if a scan was otherwise not covered.
std::uint64_t offlineChecksumOf(const std::vector<FeedStep>& steps, const std::set<int>& skip = {},
                                int* broken = nullptr);

}  // namespace ogf::testing
