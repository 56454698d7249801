// Grid-based FastSLAM with the improved proposal and selective resampling (Grisetti, Stachniss, Burgard,
// "Improved Techniques for Grid Mapping with Rao-Blackwellized Particle Filters", IEEE T-RO 2007), as the
// lecture "Robot Mapping: Grid-Based FastSLAM" (G. D. Tipaldi, L. Spinello, W. Burgard, University of
// Freiburg) presents it. Each particle holds a pose, a weight, a trajectory (shared tree) and a
// copy-on-write grid. For every scan after the robot moved linear_update_m or angular_update_rad, per
// particle:
//   1. odometry prediction g = p(x | x_{t−1}, u); with two-step sampling (Stachniss et al. 2007) the scan
//      matcher starts from a draw of g, otherwise from g's mean;
//   2. x* = argmax log p(z | x, m) + log g(x) (scan_matcher.hpp);
//   3. K poses around x*, τ = p(z | x, m)·g(x), x_t ~ N(μ, Σ), w ← w·η (improved_proposal.hpp); when the
//      match is not trusted, x_t ~ g and w ← w·p(z | x_t, m) (the plain FastSLAM proposal);
//   4. the scan is added to the particle's grid at x_t;
// then n_eff of the weights decides on low-variance resampling (resampling.hpp). The best particle (the
// largest accumulated log weight) gives the output. Deterministic for a given seed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/slam/improved_proposal.hpp"
#include "ogf/slam/map_update.hpp"
#include "ogf/slam/motion_model.hpp"
#include "ogf/slam/planar_scan.hpp"
#include "ogf/slam/scan_matcher.hpp"
#include "ogf/slam/tiled_grid.hpp"
#include "ogf/slam/trajectory.hpp"

namespace ogf::slam {

struct GridFastSlamConfig {
  std::size_t particles = 30;
  double grid_resolution_m = 0.05;  // gmapping's delta
  // A scan is processed once the robot moved this far since the last processed one. gmapping's ROS
  // defaults are 1.0 m / 0.5 rad; shorter steps give the matcher more overlap between scans.
  double linear_update_m = 0.5;
  double angular_update_rad = 0.25;
  double resample_threshold = 0.5;  // resample when n_eff < threshold·N (gmapping's resampleThreshold)
  // Tempering of the weights before normalisation, gmapping's obsSigmaGain: w̃ ∝ exp(l / (gain·N)).
  // A laser's beams are not independent, so the product of 180 beam likelihoods is far too peaked.
  double observation_gain = 3.0;
  // In the weights (τ, η and the fallback's p(z | x, m)) a beam with no endpoint near it counts as this
  // far off; 0 takes the matcher's unmatched_distance_m. The hill climbing keeps the matcher's value.
  // gmapping charges an unexplained beam 50× a beam 0.1 m off (scanmatcher.h: −0.5/lsigma against
  // −d²/lsigma); at the matcher's 0.1 m the weights hardly told the particle closing ACES's loop from the
  // others (loop closed on 0 of 3 seeds; with 0.3 m on 3 of 3; docs/slam.md).
  double weight_unmatched_distance_m = 0.3;
  bool sample_proposal = true;    // draw x_t from N(μ, Σ); false keeps x* (scan-matching odometry)
  bool two_step_sampling = true;  // start each particle's match from a motion-model draw
  // Scans between processed ones are matched against the best particle's map (not added to it), so
  // their poses come from the matcher instead of odometry alone. Costs one match per such scan.
  bool match_skipped_scans = true;
  std::uint64_t seed = 42;

  MotionModelConfig motion;
  ScanMatcherConfig matcher;
  MapUpdateConfig map_update;
  ProposalConfig proposal;

  // One particle keeping the scan matcher's maximum: "improved odometry", with the update distances and
  // matcher settings measured best for it (shorter steps, heading starts, unmatched beams costlier).
  // PoseCorrector takes only its particle count and sampling switches; ogf-slam2d its other values
  // where no flag overrides them.
  static GridFastSlamConfig scanMatching();

  // The first wrong field, with its path ("matcher.beam_stride must be >= 1 (got 0)").
  Status validate() const;
};

struct Particle {
  Pose2 pose;
  double log_weight = 0.0;        // since the last resampling (gmapping's weight)
  double log_weight_total = 0.0;  // over the whole run, inherited through resampling (gmapping's weightSum)
  TiledGrid map;
  std::shared_ptr<const TrajectoryNode> node;
};

// A scan between processed ones, located by matching it against the best particle's map: its pose
// relative to that particle's node of scan `base_scan_id`.
struct SkippedScanPose {
  std::uint64_t scan_id = 0;
  std::uint64_t base_scan_id = 0;
  Pose2 relative;  // node pose⁻¹ ⊕ matched pose
};

struct GridFastSlamStatistics {
  std::size_t scans_seen = 0;
  std::size_t scans_processed = 0;
  std::size_t resamplings = 0;
  std::size_t untrusted_matches = 0;  // particle steps that fell back to the motion model
  double last_neff = 0.0;
};

class GridFastSlam {
 public:
  static Result<GridFastSlam> create(const GridFastSlamConfig& config);

  // One scan, taken at `odometry` (the odometry pose at the scan's time). The first scan anchors the
  // map at its odometry pose. Returns whether the scan was processed (the robot moved enough).
  // `scan_id` must increase from call to call.
  bool addScan(std::uint64_t scan_id, const Pose2& odometry, const PlanarScan& scan);

  const GridFastSlamConfig& config() const { return config_; }
  const std::vector<Particle>& particles() const { return particles_; }
  const GridFastSlamStatistics& statistics() const { return stats_; }
  std::size_t bestParticle() const;
  // The best particle's current estimate for a scan at `odometry`: its last pose composed with the
  // odometry since. Before the first scan, `odometry` itself.
  Pose2 currentPose(const Pose2& odometry) const;
  std::vector<TrajectoryPoint> bestTrajectory() const;
  // Matched poses of the scans between processed ones (match_skipped_scans), by increasing scan_id.
  const std::vector<SkippedScanPose>& skippedScanPoses() const { return skipped_; }
  // The pose of scan `scan_id` taken at `odometry`, with hindsight: the best particle's node of the
  // scan, or its last node before the scan composed with the scan's matched offset (when it was matched
  // from that node) or with the odometry since. `points` is bestTrajectory().
  Pose2 poseWithHindsight(const std::vector<TrajectoryPoint>& points, std::uint64_t scan_id,
                          const Pose2& odometry) const;
  const TiledGrid& bestMap() const { return particles_[bestParticle()].map; }

 private:
  explicit GridFastSlam(const GridFastSlamConfig& config);
  void moveParticle(Particle& p, const MotionGaussian& g, const PreparedScan& scan);
  void resampleIfDegenerate();
  // log p(z | x, m) for the weights: the matcher's sum with unmatched beams at weight_unmatched_distance_m.
  double weightLogLikelihood(const ScanLikelihood& l) const;
  void locateSkippedScan(std::uint64_t scan_id, const Pose2& step, const PlanarScan& scan);

  GridFastSlamConfig config_;
  MotionModel motion_;
  ScanMatcher matcher_;
  std::mt19937_64 rng_;
  std::vector<Particle> particles_;
  std::optional<Pose2> last_odometry_;      // odometry of the last processed scan
  std::optional<Pose2> last_skipped_pose_;  // matched pose of the latest scan if it was skipped
  std::vector<SkippedScanPose> skipped_;
  GridFastSlamStatistics stats_;
};

}  // namespace ogf::slam
