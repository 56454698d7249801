// The benchmark's ground-truth relations (Kümmerle et al. 2009): "t1 t2 x y z roll pitch yaw", the motion
// from the robot pose at laser stamp t1 to the one at t2 in the frame of the first (T1^-1 * T2), metres
// and radians (docs/test-data.md §3.3); and the metric over them (§3.4).
#pragma once

#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam_io/carmen_log.hpp"

namespace ogf::slam_io {

struct Relation {
  double t1 = 0.0;
  double t2 = 0.0;
  Pose2 motion;  // x, y, yaw; z, roll and pitch are zero in the 2-D files and are checked to be
  std::size_t line = 0;
};

// Parses a whole relations file; an error names the source and line.
Result<std::vector<Relation>> readRelations(std::istream& in, const std::string& source_name);

// A stamped trajectory (e.g. read back from a result log), sorted by time.
struct StampedPose {
  double t = 0.0;
  Pose2 pose;
};

struct ErrorStatistics {
  double mean = 0.0;
  double std = 0.0;  // sample standard deviation (N - 1)
  double max = 0.0;
  std::size_t count = 0;
};

struct RelationMetric {
  ErrorStatistics translation;    // metres, sqrt(dx^2 + dy^2)
  ErrorStatistics rotation_deg;   // degrees, |dyaw| normalised to (-180, 180]
  std::size_t unmatched = 0;      // relations whose stamps had no pose within the tolerance
  // The squared errors (metricEvaluator -q), which the published tables give beside the absolute ones.
  ErrorStatistics translation_squared;   // m^2, dx^2 + dy^2
  ErrorStatistics rotation_squared_deg;  // deg^2, dyaw^2
};

// For each relation, the poses with the nearest stamps (within `tolerance_s`), their relative motion
// T(t1)^-1 T(t2), and the component-wise difference from the reference (metricEvaluator's definition).
RelationMetric evaluateRelations(const std::vector<StampedPose>& trajectory,
                                 const std::vector<Relation>& relations, double tolerance_s = 0.1);

}  // namespace ogf::slam_io
