// The scores of a map against ground truth: see map_scores.hpp.
#include "ogf/eval/map_scores.hpp"

#include <algorithm>
#include <vector>

namespace ogf::eval {
namespace {

constexpr std::uint8_t kTruthFree = 0;
constexpr std::uint8_t kTruthOccupied = 1;

double share(std::int64_t num, std::int64_t den) { return den > 0 ? static_cast<double>(num) / static_cast<double>(den) : 0.0; }

}  // namespace

double rocAuc(std::span<const double> positives, std::span<const double> negatives) {
  if (positives.empty() || negatives.empty()) return 0.5;
  // Mann-Whitney: sort everything once, give tied scores their mean rank, sum the positives' ranks.
  struct Scored {
    double score;
    bool positive;
  };
  std::vector<Scored> all;
  all.reserve(positives.size() + negatives.size());
  for (double p : positives) all.push_back({p, true});
  for (double n : negatives) all.push_back({n, false});
  std::sort(all.begin(), all.end(), [](const Scored& a, const Scored& b) { return a.score < b.score; });
  double positive_rank_sum = 0.0;
  for (std::size_t i = 0; i < all.size();) {
    std::size_t j = i;
    std::int64_t tied_positives = 0;
    while (j < all.size() && all[j].score == all[i].score) tied_positives += all[j++].positive ? 1 : 0;
    const double mean_rank = (static_cast<double>(i + 1) + static_cast<double>(j)) / 2.0;  // ranks i+1 .. j
    positive_rank_sum += mean_rank * static_cast<double>(tied_positives);
    i = j;
  }
  const auto np = static_cast<double>(positives.size());
  const auto nn = static_cast<double>(negatives.size());
  return (positive_rank_sum - np * (np + 1.0) / 2.0) / (np * nn);
}

MapScores scoreMap(std::span<const std::uint8_t> truth, std::span<const CellEstimate> estimates,
                   std::span<const std::uint8_t> ray_end) {
  MapScores s;
  std::vector<double> pos, neg;
  const std::size_t n = std::min(truth.size(), estimates.size());
  const bool gaps = ray_end.size() >= n && n > 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t t = truth[i];
    if (t != kTruthFree && t != kTruthOccupied) continue;
    const CellEstimate& e = estimates[i];
    ++s.known;
    if (e.cell_class != 0) ++s.classified;
    if (t == kTruthOccupied) {
      ++s.truth_occupied;
      pos.push_back(e.probability);
      if (e.cell_class > 0) ++s.true_occupied;
      if (e.cell_class < 0) ++s.false_free;
      if (gaps && ray_end[i] == 0) {
        ++s.gap_cells;
        if (e.cell_class > 0) ++s.gap_filled;
      }
    } else {
      ++s.truth_free;
      neg.push_back(e.probability);
      if (e.cell_class > 0) ++s.false_occupied;
      if (gaps && ray_end[i] == 0 && e.cell_class > 0) ++s.false_filled;
      if (e.cell_class < 0) ++s.true_free;
    }
  }
  s.correct = s.true_occupied + s.true_free;
  s.accuracy = share(s.correct, s.known);
  s.precision = share(s.true_occupied, s.true_occupied + s.false_occupied);
  s.recall = share(s.true_occupied, s.truth_occupied);
  s.coverage = share(s.classified, s.known);
  s.gap_fill = share(s.gap_filled, s.gap_cells);
  s.auc = rocAuc(pos, neg);
  return s;
}

SweptScores scoreSwept(std::span<const std::uint8_t> truth, std::span<const std::uint8_t> swept,
                       std::span<const CellEstimate> estimates) {
  SweptScores s;
  const std::size_t n = std::min({truth.size(), swept.size(), estimates.size()});
  for (std::size_t i = 0; i < n; ++i) {
    if (swept[i] != kTruthOccupied || truth[i] != kTruthFree) continue;
    ++s.cells;
    s.left_occupied += estimates[i].cell_class > 0 ? 1 : 0;
  }
  return s;
}

UnionCoverage unionCoverage(std::span<const std::uint8_t> truth, const std::vector<std::vector<CellEstimate>>& maps) {
  std::int64_t known = 0, any = 0, consistent = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] > 1) continue;  // unobservable
    ++known;
    bool occupied = false, free = false;
    for (const auto& map : maps) {
      occupied = occupied || map[i].cell_class > 0;
      free = free || map[i].cell_class < 0;
    }
    if (occupied || free) ++any;
    if (occupied != free) ++consistent;
  }
  if (known == 0) return {};
  return {static_cast<double>(any) / static_cast<double>(known), static_cast<double>(consistent) / static_cast<double>(known)};
}

}  // namespace ogf::eval
