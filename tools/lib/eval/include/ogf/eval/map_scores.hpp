// How well a map classifies a known world: the scores ogf-eval prints for the OGF and for OctoMap, computed
// on the ground-truth grid of a simulator run. Pure: the caller classifies every truth cell with its map
// first (CellEstimate, one per truth cell, same order as GroundTruth::cells).
//
// Definitions (truth cells that are free or occupied are "known"; unobservable ones are left out):
//   accuracy   eq. (13) of Sun et al. over the known cells: share classified as their truth (occupied as
//              +1, free as -1); a cell the map leaves unknown (class 0, or never allocated) counts as wrong.
//   precision  of "occupied": truth-occupied among the cells classified occupied.
//   recall     of "occupied": classified occupied among the truth-occupied cells.
//   auc        ROC AUC of the probabilities, truth-occupied (positive) against truth-free (negative) cells,
//              ties counted half (the Mann-Whitney statistic); unallocated cells score the prior 0.5.
//   coverage   share of the known cells the map classifies (class != 0).
//   gap_*      truth-occupied cells in which no ray of the run ended (`ray_end[i] == 0`): how many, and how
//              many of them the map classifies occupied anyway (filled from their neighbours); and the
//              cells the map fills wrongly: classed occupied, no ray ended there, truth free.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::eval {

struct CellEstimate {
  std::int8_t cell_class = 0;  // +1 occupied, -1 free, 0 unknown
  double probability = 0.5;    // of occupancy
};

struct MapScores {
  std::int64_t known = 0;           // truth free + occupied cells
  std::int64_t truth_occupied = 0;
  std::int64_t truth_free = 0;
  std::int64_t correct = 0;
  std::int64_t true_occupied = 0;   // truth occupied, classified occupied
  std::int64_t false_occupied = 0;  // truth free, classified occupied
  std::int64_t true_free = 0;       // truth free, classified free
  std::int64_t false_free = 0;      // truth occupied, classified free
  std::int64_t classified = 0;      // known cells with class != 0
  std::int64_t gap_cells = 0;       // truth occupied, no ray ended there
  std::int64_t gap_filled = 0;      // ... and classified occupied
  std::int64_t false_filled = 0;    // truth free, no ray ended there, classified occupied
  double accuracy = 0, precision = 0, recall = 0, auc = 0.5, coverage = 0, gap_fill = 0;
};

// `truth` holds ogf::sim::CellClass bytes (0 free, 1 occupied, 2 unobservable); `estimates` and `ray_end`
// (1 where a ray of the run ended, i.e. an occupied measurement; may be empty: no gap scores) are aligned
// with it.
MapScores scoreMap(std::span<const std::uint8_t> truth, std::span<const CellEstimate> estimates,
                   std::span<const std::uint8_t> ray_end);

// What moving solids left behind: among the cells a moving solid passed through that are free in the truth
// (swept.grid of an ogf-sim run with --movers, aligned with the truth), how many the map classes occupied
// at the end.
struct SweptScores {
  std::int64_t cells = 0;          // swept and truth-free
  std::int64_t left_occupied = 0;  // ... classed occupied
};
SweptScores scoreSwept(std::span<const std::uint8_t> truth, std::span<const std::uint8_t> swept,
                       std::span<const CellEstimate> estimates);

// Several maps of one world, each from some of the sources (lidars, robots) alone, each aligned with
// `truth`: the coverage of their union, as shares of the known truth cells (0 when nothing is known).
struct UnionCoverage {
  double any = 0;         // at least one map classifies the cell (class != 0)
  double consistent = 0;  // ... and no map classifies it the other way (occupied against free): where two
                          // sources contradict each other their union holds no class a shared map could match
};
UnionCoverage unionCoverage(std::span<const std::uint8_t> truth, const std::vector<std::vector<CellEstimate>>& maps);

// ROC AUC of scores: the probability that a random positive scores above a random negative, ties half.
// 0.5 when either set is empty.
double rocAuc(std::span<const double> positives, std::span<const double> negatives);

}  // namespace ogf::eval
