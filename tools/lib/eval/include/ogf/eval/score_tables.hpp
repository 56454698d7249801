// The tables ogf-eval prints, as text: the scores of each map against the truth (one column per map), and
// the two-column tables of the held-out test and of a static capture's own returns. Fixed-width columns
// (34 characters of label, 12 per map) so that runs can be compared with diff.
#pragma once

#include <ogf/sim/ground_truth.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ogf/eval/held_out.hpp"
#include "ogf/eval/map_scores.hpp"
#include "ogf/eval/return_scores.hpp"

namespace ogf::eval {

// One map's column of the score table.
struct MapColumn {
  std::string name;
  MapScores scores;
  std::int64_t occupied_cells = 0;  // classified occupied, inside the truth grid
  std::int64_t free_cells = 0;
  std::string map_cells;            // cells the map holds, as text
  std::optional<SweptScores> swept;
};

// The map's estimate of every observable truth cell (unobservable ones stay unknown), in the truth's order.
template <class Estimate>
std::vector<CellEstimate> classifyTruth(const sim::GroundTruth& truth, Estimate estimate) {
  std::vector<CellEstimate> out(truth.cells.size());
  for (std::size_t i = 0; i < truth.cells.size(); ++i) {
    if (truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Unobservable)) continue;
    out[i] = estimate(truth.keyOf(i));
  }
  return out;
}

// The column of a map whose estimates of the truth cells are `estimates`; `ray_end` as scoreMap takes it.
MapColumn makeColumn(std::string name, const sim::GroundTruth& truth, const std::vector<CellEstimate>& estimates,
                     const std::vector<std::uint8_t>& ray_end, std::string map_cells);

// The score table; `gaps` adds the gap-filling rows, a first column with swept scores the moving-solid rows.
std::string scoreTable(const std::vector<MapColumn>& columns, bool gaps);

// A table under a title (after a blank line): a header of `names`, then one row per label.
using TableRows = std::vector<std::pair<std::string, std::vector<std::string>>>;
std::string pairTable(const std::string& title, const std::vector<std::string>& names, const TableRows& rows);

// The held-out test's table, one column per map.
std::string heldOutTable(const HeldOutSplit& split, std::uint64_t seed, const std::vector<std::string>& names,
                         const std::vector<HeldOutScores>& scores);

// A static capture's own returns, scored on the OGF and the OctoMap (from-to: the ranges scored);
// `map_cells` is what each map holds, as text.
std::string returnsTable(double from_m, double to_m, const std::vector<ReturnScores>& scores,
                         const std::vector<std::string>& map_cells);

}  // namespace ogf::eval
