// What change of a cell is worth sending on OGF_MAP_DELTA. A client holds, per cell, the value last
// published; the mapper compares each changed cell with that value (not with the cell's previous value,
// so slow drifts still go out once they add up):
//   - a class change always (free / unknown / occupied, eq. (3) of Sun et al.: what planners read);
//   - otherwise a quantised probability at least `probability_step` from the published one;
//   - otherwise, when `variance_step` > 0, a variance that moved by more than that fraction of the
//     published variance (of a cell published before).
// A client's map then has the mapper's class for every cell and its probability within the step, at a
// fraction of the cells: most changes of a street scan are cells drifting by a few ten-thousandths.
// probability_step 0 sends every change of quantised probability or class.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "ogf/delta/published_cell.hpp"

namespace ogf::delta {

// The default sends every visible change; ogf-mapper's deltas.probability_step is 0.02.
struct PublishingRule {
  double probability_step = 0.0;  // in probability (0..1); 0: any change of the quantised probability
  double variance_step = 0.0;      // relative to the published variance; 0: variance alone sends nothing

  // The step in PROBABILITY_SCALE units, at least 1 (a change of the quantised value).
  std::int32_t quantisedStep() const {
    const double s = std::round(std::clamp(probability_step, 0.0, 1.0) * kProbabilityScale);
    return std::max<std::int32_t>(1, static_cast<std::int32_t>(s));
  }
};

// Why a cell goes out; kClass outranks kProbability when a budget defers cells.
enum class Worth : std::uint8_t { kNothing, kProbability, kClass };

// `now` against `published` (the prior for a cell never published), with the step in quantised units
// (PublishingRule::quantisedStep, taken once per update).
inline Worth worthSending(const PublishedCell& now, const PublishedCell& published, std::int32_t step,
                          double variance_step) {
  if (now.cell_class != published.cell_class) return Worth::kClass;
  if (std::abs(static_cast<std::int32_t>(now.probability) - published.probability) >= step) return Worth::kProbability;
  // A cell never published has no variance to compare with (the prior's 0 stands for none).
  const double was = published.variance;
  if (variance_step > 0 && was > 0 && std::abs(static_cast<double>(now.variance) - was) > variance_step * was)
    return Worth::kProbability;
  return Worth::kNothing;
}

}  // namespace ogf::delta
