// Test helper: two robots on one bus for a real ogf-mapper, r1 carrying sensor "front" and r2 sensor
// "rear", each with its own odometry (SCAN_R1/POSE_R1, SCAN_R2/POSE_R2): the mapper's sources, and the
// feed that drives both round the scan feeder's room, r2 `apart` metres further along x.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <ogf/mapper_status_t.hpp>

#include <chrono>

#include "scan_feeder.hpp"
#include "support/daemon_process.hpp"

namespace ogf::testing {

inline constexpr const char* kTwoRobotsSources =
    "sources:\n"
    "  - {name: front, robot: r1, scan_channel: SCAN_R1, pose_channel: POSE_R1}\n"
    "  - {name: rear, robot: r2, scan_channel: SCAN_R2, pose_channel: POSE_R2}\n";

// Publishes `steps` scans of each robot with their odometry, one step at a time (waiting until the
// mapper mapped the step's two scans, so none waits behind another).
inline void feedTwoRobots(lcm::LCM& lcm, const DaemonProcess<ogf::mapper_status_t>& mapper, int steps,
                          double apart) {
  for (int i = 0; i < steps; ++i) {
    const auto step = feedStep(i);
    for (auto p : step.poses) {
      lcm.publish("POSE_R1", &p);
      p.position[0] += apart;
      lcm.publish("POSE_R2", &p);
    }
    lcm.publish("SCAN_R1", &step.scan);
    lcm.publish("SCAN_R2", &step.scan);
    mapper.waitForStatus([&](const ogf::mapper_status_t& s) { return s.scans_mapped >= 2 * (i + 1); },
                         std::chrono::seconds(10));
  }
}

}  // namespace ogf::testing
