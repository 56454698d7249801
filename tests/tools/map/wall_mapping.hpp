// Test helper: an offline run that mapped three static scans of a wall 4.1 m ahead (synthetic_scan.hpp).
#pragma once

#include <gtest/gtest.h>

#include <utility>

#include "ogf/map_io/offline_mapping.hpp"
#include "synthetic_scan.hpp"

namespace ogf::testing {

inline map_io::OfflineMapping wallMapping() {
  pipeline::MapperConfig config;
  config.setResolution(0.2);
  config.fusion.measurement.max_range_m = 10.0;
  auto run = map_io::OfflineMapping::create(config);
  EXPECT_TRUE(run.ok());
  const auto scan = wallScan(4.1);
  for (int i = 0; i < 3; ++i) run->addStaticScan(scan, Eigen::Isometry3d::Identity());
  return std::move(*run);
}

}  // namespace ogf::testing
