// Where the rays of a run ended, on the truth grid: the cells of the run's occupied measurements, the
// input of the gap-filling score (map_scores.hpp: a truth-occupied cell no ray ended in is a gap).
#pragma once

#include <ogf/core/measurement.hpp>
#include <ogf/sim/ground_truth.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::eval {

// Sets ray_end[i] = 1 for every truth cell i holding an occupied measurement of `measurements`; cells
// outside the truth grid and free measurements are ignored. `ray_end` has one entry per truth cell.
void markRayEnds(const sim::GroundTruth& truth, std::span<const Measurement> measurements,
                 std::vector<std::uint8_t>& ray_end);

}  // namespace ogf::eval
