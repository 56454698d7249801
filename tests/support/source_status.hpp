// Test helper: one source of a mapper status, as a test publishes it in place of ogf-mapper: `robot` and
// `name`, its channels named after them (VELODYNE_SCAN_<name>, POSE_<robot>), inputs OK, and `trail` as
// its sensor's positions; the counters are the test's to set.
#pragma once

#include <ogf/mapper_status_t.hpp>
#include <ogf/source_status_t.hpp>

#include <array>
#include <string>
#include <vector>

namespace ogf::testing {

inline ogf::source_status_t sourceStatus(const std::string& robot, const std::string& name,
                                         const std::vector<std::array<float, 3>>& trail) {
  ogf::source_status_t s{};
  s.name = name;
  s.robot = robot;
  s.scan_channel = "VELODYNE_SCAN_" + name;
  s.pose_channel = "POSE_" + robot;
  s.inputs = ogf::mapper_status_t::INPUTS_OK;
  for (const auto& p : trail) s.trail.push_back({p[0], p[1], p[2]});
  s.trail_size = static_cast<std::int16_t>(trail.size());
  return s;
}

}  // namespace ogf::testing
