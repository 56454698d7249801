// Test helper: scans sent into a real ogf-mapper at the VLP-16's 10 scans a second (the feeder's room drive,
// tests/integration/scan_feeder.hpp) while another process attacks the bus, and the figures that tell
// whether mapping waited: the real source's scans mapped and dropped, the largest gap between two map
// deltas while the scans came, and the mapper's resident memory sampled through the run.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

namespace ogf::testing {

struct SensorRateReplay {
  std::filesystem::path dir;  // the mapper's state directory, configuration and log go here, named by `name`
  std::string url;
  std::string name;
  std::string config;  // YAML, after `status_interval_s: 0.1`
  int scans = 100;
  int points = 16 * 1800;
  std::string scan_channel = "VELODYNE_SCAN";  // the source whose scans are sent and counted
  std::string pose_channel = "POSE";
  // When set, runs in a forked process from before the first scan until every scan is accounted for, then
  // is killed; `first_scan` is when scan 0 is sent, on the steady clock.
  std::function<void(lcm::LCM& bus, std::chrono::steady_clock::time_point first_scan)> attack;
};

struct ReplayFigures {
  ogf::mapper_status_t status{};
  ogf::source_status_t source{};  // the source on SensorRateReplay::scan_channel
  double largest_gap_s = 0;
  std::int64_t deltas = 0;
  std::int64_t first_rss_bytes = 0;
  std::int64_t peak_rss_bytes = 0;
};

// Runs the replay (gtest failures for a mapper that does not start or does not account for every scan).
ReplayFigures replayAtSensorRate(const SensorRateReplay& run);

// One line of figures for the test's output.
std::string figuresLine(const std::string& label, const ReplayFigures& f);

}  // namespace ogf::testing
