// The held-out test: see held_out.hpp.
#include "ogf/eval/held_out.hpp"

#include <ogf/fusion/ray_caster.hpp>

#include <algorithm>
#include <cmath>

namespace ogf::eval {
namespace {

// SplitMix64's finaliser: a well-mixed 64-bit hash of one word.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

bool HeldOutSplit::heldOut(std::int64_t scan, std::size_t ray) const {
  const std::uint64_t h = mix(mix(seed_ ^ static_cast<std::uint64_t>(scan)) ^ static_cast<std::uint64_t>(ray));
  return static_cast<double>(h >> 11) * 0x1.0p-53 < share_;
}

void HeldOutScorer::Tally::count(const CellEstimate& e, bool is_positive) {
  const auto bin = static_cast<std::size_t>(std::lround(std::clamp(e.probability, 0.0, 1.0) * (kBins - 1)));
  if (is_positive) {
    ++positive[bin];
    positives_occupied += e.cell_class > 0 ? 1 : 0;
  } else {
    ++negative[bin];
    negatives_free += e.cell_class < 0 ? 1 : 0;
  }
}

HeldOutRanking HeldOutScorer::Tally::ranking() const {
  HeldOutRanking s;
  // Mann-Whitney over the bins: a positive beats every negative in a lower bin and ties half of its own.
  double wins = 0.0;
  std::int64_t below = 0;
  for (std::size_t b = 0; b < kBins; ++b) {
    s.positives += positive[b];
    s.negatives += negative[b];
    wins += static_cast<double>(positive[b]) * (static_cast<double>(below) + 0.5 * static_cast<double>(negative[b]));
    below += negative[b];
  }
  if (s.positives > 0 && s.negatives > 0) {
    s.auc = wins / (static_cast<double>(s.positives) * static_cast<double>(s.negatives));
  }
  s.positives_occupied = s.positives > 0 ? static_cast<double>(positives_occupied) / static_cast<double>(s.positives) : 0.0;
  s.negatives_free = s.negatives > 0 ? static_cast<double>(negatives_free) / static_cast<double>(s.negatives) : 0.0;
  return s;
}

void HeldOutScorer::count(const CellKey& k, bool positive, const Estimate& estimate, const Seen& seen) {
  const CellEstimate e = estimate(k);
  all_.count(e, positive);
  if (!seen(k)) unseen_.count(e, positive);
}

void HeldOutScorer::add(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, const Estimate& estimate,
                        const Seen& seen) {
  if (!origin.allFinite() || !endpoint.allFinite()) return;
  const Eigen::Vector3d ray = endpoint - origin;
  const double range = ray.norm();
  if (range < min_range_) return;
  ++rays_;
  const bool cut = range > max_range_;
  const Eigen::Vector3d end = cut ? Eigen::Vector3d(origin + ray * (max_range_ / range)) : endpoint;
  const fusion::RayCaster cells(origin, end, resolution_);
  for (const CellKey k : cells) count(k, false, estimate, seen);
  if (!cut) count(cells.endCell(), true, estimate, seen);
}

HeldOutScores HeldOutScorer::scores() const {
  HeldOutScores s;
  static_cast<HeldOutRanking&>(s) = all_.ranking();
  s.rays = rays_;
  s.unseen = unseen_.ranking();
  return s;
}

}  // namespace ogf::eval
