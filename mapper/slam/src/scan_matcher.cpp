// The likelihood-field scan matcher: gmapping's windowed endpoint search and its hill climbing.
#include "ogf/slam/scan_matcher.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "config_errors.hpp"

namespace ogf::slam {

Status ScanMatcherConfig::validate() const {
  if (!(min_range_m >= 0.0)) return fieldError("min_range_m", "must be >= 0", min_range_m);
  if (!(usable_range_m > min_range_m) || !std::isfinite(usable_range_m)) {
    return fieldError("usable_range_m", "must be finite and > min_range_m", usable_range_m);
  }
  if (beam_stride < 1) return fieldError("beam_stride", "must be >= 1", beam_stride);
  if (search_window_cells < 0 || search_window_cells > 8) {
    return fieldError("search_window_cells", "must be in [0, 8]", search_window_cells);
  }
  if (!(occupied_threshold > 0.0 && occupied_threshold < 1.0)) {
    return fieldError("occupied_threshold", "must be in (0, 1)", occupied_threshold);
  }
  if (!(likelihood_sigma_m > 0.0) || !std::isfinite(likelihood_sigma_m)) {
    return fieldError("likelihood_sigma_m", "must be > 0", likelihood_sigma_m);
  }
  if (!(unmatched_distance_m > 0.0) || !std::isfinite(unmatched_distance_m)) {
    return fieldError("unmatched_distance_m", "must be > 0", unmatched_distance_m);
  }
  if (!(linear_step_m > 0.0)) return fieldError("linear_step_m", "must be > 0", linear_step_m);
  if (!(angular_step_rad > 0.0)) return fieldError("angular_step_rad", "must be > 0", angular_step_rad);
  if (refinements < 0 || refinements > 20)
    return fieldError("refinements", "must be in [0, 20]", refinements);
  if (max_evaluations < 1) return fieldError("max_evaluations", "must be >= 1", max_evaluations);
  if (heading_starts < 0 || heading_starts > 10)
    return fieldError("heading_starts", "must be in [0, 10]", heading_starts);
  if (!(heading_start_step_rad > 0.0) || !std::isfinite(heading_start_step_rad)) {
    return fieldError("heading_start_step_rad", "must be > 0", heading_start_step_rad);
  }
  if (!(min_matched_fraction >= 0.0 && min_matched_fraction <= 1.0)) {
    return fieldError("min_matched_fraction", "must be in [0, 1]", min_matched_fraction);
  }
  return okStatus();
}

PreparedScan ScanMatcher::prepare(const PlanarScan& scan, double grid_resolution_m) const {
  PreparedScan out;
  out.beams.reserve(scan.ranges_m.size() / static_cast<std::size_t>(config_.beam_stride) + 1);
  for (std::size_t i = 0; i < scan.ranges_m.size(); i += static_cast<std::size_t>(config_.beam_stride)) {
    const float r = scan.ranges_m[i];
    if (!scan.isValid(r) || scan.isNoReturn(r)) continue;
    const double range = r;
    if (range < config_.min_range_m || range > config_.usable_range_m) continue;
    const double a = scan.sensor_pose.theta + scan.bearing(i);
    const double c = std::cos(a), s = std::sin(a);
    const double free_range = std::max(0.0, range - grid_resolution_m);
    out.beams.push_back({scan.sensor_pose.x + range * c, scan.sensor_pose.y + range * s,
                         scan.sensor_pose.x + free_range * c, scan.sensor_pose.y + free_range * s});
  }
  return out;
}

ScanLikelihood ScanMatcher::likelihood(const TiledGrid& grid, const Pose2& x,
                                       const PreparedScan& scan) const {
  const double c = std::cos(x.theta), s = std::sin(x.theta);
  const double inv_two_sigma2 = 1.0 / (2.0 * config_.likelihood_sigma_m * config_.likelihood_sigma_m);
  const double unmatched_d2 = config_.unmatched_distance_m * config_.unmatched_distance_m;
  const int w = config_.search_window_cells;
  ScanLikelihood out;
  out.beams = scan.beams.size();
  for (const auto& b : scan.beams) {
    const double hx = x.x + c * b.hit_x - s * b.hit_y, hy = x.y + s * b.hit_x + c * b.hit_y;
    const double fx = x.x + c * b.free_x - s * b.free_y, fy = x.y + s * b.free_x + c * b.free_y;
    const CellIndex hit = grid.cellOf(hx, hy), free = grid.cellOf(fx, fy);
    const int fdx = free.x - hit.x, fdy = free.y - hit.y;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (int dy = -w; dy <= w; ++dy) {
      for (int dx = -w; dx <= w; ++dx) {
        const CellIndex cell{hit.x + dx, hit.y + dy};
        if (grid.occupancy(cell) <= config_.occupied_threshold) continue;
        if (grid.occupancy({cell.x + fdx, cell.y + fdy}) >= config_.occupied_threshold) continue;
        const Eigen::Vector2d mean = grid.meanEndpoint(cell);
        const double ex = hx - mean.x(), ey = hy - mean.y();
        best_d2 = std::min(best_d2, ex * ex + ey * ey);
      }
    }
    if (best_d2 < unmatched_d2) {
      ++out.matched;
      out.log_likelihood -= best_d2 * inv_two_sigma2;
    } else {
      out.log_likelihood -= unmatched_d2 * inv_two_sigma2;
    }
  }
  return out;
}

MatchResult ScanMatcher::match(const TiledGrid& grid, const Pose2& start, const PreparedScan& scan,
                               const MotionGaussian* prior) const {
  MatchResult best = climb(grid, start, scan, prior);
  int evaluations = best.evaluations;
  // Further climbs from headings ±k·heading_start_step_rad around `start`: a heading error larger than
  // the climb's first step can leave it on a wrong local maximum. The best objective wins.
  for (int k = 1; k <= config_.heading_starts; ++k) {
    for (const double sign : {1.0, -1.0}) {
      const Pose2 s{start.x, start.y,
                    normalizeAngle(start.theta + sign * k * config_.heading_start_step_rad)};
      const MatchResult m = climb(grid, s, scan, prior);
      evaluations += m.evaluations;
      if (m.objective > best.objective) best = m;
    }
  }
  best.evaluations = evaluations;
  return best;
}

MatchResult ScanMatcher::climb(const TiledGrid& grid, const Pose2& start, const PreparedScan& scan,
                               const MotionGaussian* prior) const {
  MatchResult best;
  const auto evaluate = [&](const Pose2& x, ScanLikelihood& l) {
    l = likelihood(grid, x, scan);
    ++best.evaluations;
    return l.log_likelihood + (prior != nullptr ? prior->logDensity(x) : 0.0);
  };
  best.pose = start;
  best.objective = evaluate(start, best.likelihood);
  double lin = config_.linear_step_m, ang = config_.angular_step_rad;
  int refinement = 0;
  while (refinement <= config_.refinements && best.evaluations + 6 <= config_.max_evaluations) {
    const std::array<Pose2, 6> moves{{{best.pose.x + lin, best.pose.y, best.pose.theta},
                                      {best.pose.x - lin, best.pose.y, best.pose.theta},
                                      {best.pose.x, best.pose.y + lin, best.pose.theta},
                                      {best.pose.x, best.pose.y - lin, best.pose.theta},
                                      {best.pose.x, best.pose.y, normalizeAngle(best.pose.theta + ang)},
                                      {best.pose.x, best.pose.y, normalizeAngle(best.pose.theta - ang)}}};
    Pose2 step_pose = best.pose;
    ScanLikelihood step_l;
    double step_objective = best.objective;
    for (const Pose2& m : moves) {
      ScanLikelihood l;
      const double o = evaluate(m, l);
      if (o > step_objective) {
        step_objective = o;
        step_pose = m;
        step_l = l;
      }
    }
    if (step_objective > best.objective) {
      best.pose = step_pose;
      best.objective = step_objective;
      best.likelihood = step_l;
    } else {
      ++refinement;
      lin *= 0.5;
      ang *= 0.5;
    }
  }
  best.converged =
      best.likelihood.beams > 0 && best.likelihood.matchedFraction() >= config_.min_matched_fraction;
  return best;
}

}  // namespace ogf::slam
