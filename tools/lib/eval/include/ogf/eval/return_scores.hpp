// How a map holds the returns it was built from, for a capture without ground truth (a real static
// capture): the share of returns whose cell the map classes occupied (what the sensor saw should be in the
// map), free or unknown, and the share of points half-way along each return's ray that the map classes
// free (the air in front of a surface should be open). Only returns whose range lies in [from, to] count,
// inside the mapped range with a margin, so that a cut ray's end is not scored as a surface.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <functional>

#include "ogf/eval/map_scores.hpp"

namespace ogf::eval {

struct ReturnScores {
  std::int64_t returns = 0;
  double occupied = 0.0;      // share of returns in cells classed occupied
  double free = 0.0;          // ... classed free
  double unknown = 0.0;       // ... neither
  double halfway_free = 0.0;  // share of half-way points in cells classed free
};

class ReturnScorer {
 public:
  using Estimate = std::function<CellEstimate(const CellKey&)>;
  ReturnScorer(double resolution, double from_m, double to_m) : resolution_(resolution), from_(from_m), to_(to_m) {}

  void add(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, const Estimate& estimate);
  ReturnScores scores() const;

 private:
  double resolution_, from_, to_;
  std::int64_t returns_ = 0, occupied_ = 0, free_ = 0, halfway_free_ = 0;
};

}  // namespace ogf::eval
