// A deterministic stand-in for a moving robot on the bus: scans of a walled room, as ogf-driver would
// publish them (per-point time offsets, device time), and odometry covering each scan before it. The same
// scans can be fed offline to a ScanMapper to know exactly the map the daemon must hold.
#pragma once

#include <ogf/lidar_scan_t.hpp>
#include <ogf/odometry_t.hpp>

#include <cstdint>
#include <vector>

namespace ogf::testing {

struct FeedStep {
  std::vector<ogf::odometry_t> poses;  // published before the scan
  ogf::lidar_scan_t scan;
};

// Scan i of a robot driving slowly round a 10 m x 8 m room (walls 2 m high), `points` rays per scan,
// scan period 100 ms, odometry at 100 Hz.
FeedStep feedStep(int i, int points = 1500);

}  // namespace ogf::testing
