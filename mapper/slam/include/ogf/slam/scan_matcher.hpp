// The scan matcher: the pose x* = argmax log p(z | x, m) + log p(x | u, x_prev) of one scan against a
// particle's grid (Grisetti et al. 2007, eq. 10–11; the lecture's "pose correction using scan matching").
// The observation model is gmapping's (ScanMatcher::likelihoodAndScore): each beam endpoint looks for the
// nearest occupied cell in a small window whose neighbour towards the sensor is free, and scores the
// distance d to the mean endpoint in that cell as a Gaussian, log p(z_i) = −d² / (2σ²), a beam with no
// such cell as if it were `unmatched_distance_m` off. The maximum is found by gmapping's hill climbing:
// try ±step in x, y and θ, take the best, halve the steps when none improves; optionally further climbs
// from headings around the start (heading_starts), the best objective winning.
// Used on its own it is "improved odometry"; the RBPF runs it per particle for the improved proposal.
#pragma once

#include <cstddef>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam/motion_model.hpp"
#include "ogf/slam/planar_scan.hpp"
#include "ogf/slam/pose2.hpp"
#include "ogf/slam/tiled_grid.hpp"

namespace ogf::slam {

struct ScanMatcherConfig {
  double usable_range_m = 25.0;  // longer beams and "no return" readings are not matched
  double min_range_m = 0.05;
  int beam_stride = 1;                // match every n-th beam (gmapping's lskip + 1)
  int search_window_cells = 1;        // endpoint searched within ±n cells (gmapping's kernelSize)
  double occupied_threshold = 0.1;    // hit frequency above which a cell is occupied (fullnessThreshold)
  double likelihood_sigma_m = 0.075;  // σ of the endpoint Gaussian (gmapping's lsigma)
  double unmatched_distance_m = 0.1;  // a beam with no occupied cell in its window counts as this far off
  double linear_step_m = 0.05;        // first hill-climbing step (gmapping's lstep)
  double angular_step_rad = 0.05;     // (gmapping's astep)
  int refinements = 5;                // step halvings before the climb stops (gmapping's iterations)
  int max_evaluations = 600;          // hard bound on likelihood evaluations per climb
  // Extra climbs started at the start heading ±k·heading_start_step_rad, k = 1..heading_starts; the
  // best objective wins (0: one climb, gmapping's behaviour).
  int heading_starts = 0;
  double heading_start_step_rad = 0.1;
  // A match whose best pose explains fewer than this share of the matchable beams is not trusted
  // (empty or foreign map): the caller falls back to odometry.
  double min_matched_fraction = 0.3;

  Status validate() const;
};

// A scan's beams in the robot frame, prepared once per scan: the endpoint and a point one cell short of
// it towards the sensor (the "free" probe of gmapping's freeDelta).
struct PreparedScan {
  struct Beam {
    double hit_x, hit_y;    // endpoint, robot frame
    double free_x, free_y;  // endpoint minus one cell along the beam, robot frame
  };
  std::vector<Beam> beams;
};

struct ScanLikelihood {
  double log_likelihood = 0.0;  // Σ log p(z_i | x, m) over the matched beams
  std::size_t matched = 0;      // beams that found an occupied cell
  std::size_t beams = 0;        // beams evaluated
  double matchedFraction() const {
    return beams == 0 ? 0.0 : static_cast<double>(matched) / static_cast<double>(beams);
  }
};

struct MatchResult {
  Pose2 pose;
  ScanLikelihood likelihood;  // at `pose`
  double objective = 0.0;     // log p(z | pose, m) + log p(pose | u, x_prev)
  int evaluations = 0;
  bool converged = false;  // the match explains enough beams to be trusted
};

class ScanMatcher {
 public:
  explicit ScanMatcher(const ScanMatcherConfig& config) : config_(config) {}
  const ScanMatcherConfig& config() const { return config_; }

  // `grid_resolution_m` sets the free probe one cell short of each endpoint.
  PreparedScan prepare(const PlanarScan& scan, double grid_resolution_m) const;

  // log p(z | x, m) of the prepared scan at robot pose `x`.
  ScanLikelihood likelihood(const TiledGrid& grid, const Pose2& x, const PreparedScan& scan) const;

  // Hill-climbs from `start` on log p(z | x, m) + log p(x | u, x_prev) (the prior term is left out when
  // `prior` is null).
  MatchResult match(const TiledGrid& grid, const Pose2& start, const PreparedScan& scan,
                    const MotionGaussian* prior) const;

 private:
  MatchResult climb(const TiledGrid& grid, const Pose2& start, const PreparedScan& scan,
                    const MotionGaussian* prior) const;

  ScanMatcherConfig config_;
};

}  // namespace ogf::slam
