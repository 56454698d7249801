// The held-out test: a map is built from most of every scan's rays and asked about the rays it never saw.
// Each held-out ray that returned says its end cell is occupied (a positive) and every cell it crossed on
// the way is free (negatives); a ray cut at max range gives negatives only. The map's predictive
// probability of occupancy ranks the positives above the negatives as well as it can: the ROC AUC of that
// ranking, and the share of positives the map classes occupied and of negatives it classes free, say how
// well the map predicts measurements it was not given, which is what a map is for. A map that only
// remembers the cells rays ended in scores its gaps at 0.5; one that fills them scores higher.
//
// Which rays are held out: a hash of (scan, ray, seed) below the share, so every map of a run is built from
// and scored on the same rays. Probabilities are counted in 10001 bins of 1e-4 (the delta stream's
// resolution), so the AUC is exact up to ties within a bin, which count half; memory stays constant however
// many cells the held-out rays cross.
//
// The same scores restricted to the cells no kept ray measured ("unseen") say what the maps predict where
// they were given nothing: an independent-cell map can only answer 0.5 there, a correlated one infers.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "ogf/eval/map_scores.hpp"

namespace ogf::eval {

class HeldOutSplit {
 public:
  // share in [0, 1): the fraction of rays held out.
  HeldOutSplit(double share, std::uint64_t seed) : share_(share), seed_(seed) {}
  bool heldOut(std::int64_t scan, std::size_t ray) const;
  double share() const { return share_; }

 private:
  double share_;
  std::uint64_t seed_;
};

struct HeldOutRanking {
  std::int64_t positives = 0;       // end cells of held-out returns
  std::int64_t negatives = 0;       // cells held-out rays crossed
  double auc = 0.5;
  double positives_occupied = 0.0;  // share of positives classed occupied
  double negatives_free = 0.0;      // share of negatives classed free
};

struct HeldOutScores : HeldOutRanking {
  std::int64_t rays = 0;
  HeldOutRanking unseen;  // the cells no kept ray measured
};

class HeldOutScorer {
 public:
  using Estimate = std::function<CellEstimate(const CellKey&)>;
  using Seen = std::function<bool(const CellKey&)>;  // whether a kept ray measured the cell

  // The rays are cut and ignored as the mapping pipeline does: closer than min_range ignored, beyond
  // max_range cut there with free cells only.
  HeldOutScorer(double resolution, double min_range_m, double max_range_m)
      : resolution_(resolution), min_range_(min_range_m), max_range_(max_range_m) {}

  // One held-out ray, asked of the map.
  void add(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, const Estimate& estimate,
           const Seen& seen);
  HeldOutScores scores() const;

 private:
  static constexpr std::size_t kBins = 10001;
  struct Tally {
    std::array<std::int64_t, kBins> positive{};
    std::array<std::int64_t, kBins> negative{};
    std::int64_t positives_occupied = 0;
    std::int64_t negatives_free = 0;
    void count(const CellEstimate& e, bool positive);
    HeldOutRanking ranking() const;
  };
  void count(const CellKey& k, bool positive, const Estimate& estimate, const Seen& seen);
  double resolution_, min_range_, max_range_;
  std::int64_t rays_ = 0;
  Tally all_;
  Tally unseen_;
};

}  // namespace ogf::eval
