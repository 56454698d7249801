// The 2-D navigation grid of a map (mapper/navigation) scored against a simulator run's ground truth, column
// by column over the same band: a truth column is occupied when a truth cell of the band's layers is occupied,
// free when every one is free (open air the sensor reaches); columns inside solids or sealed off are not
// scored. What a planner needs: the free columns free (a path exists) and the occupied ones occupied (no
// collision); an unknown column is neither.
#pragma once

#include <ogf/navigation/nav_band.hpp>
#include <ogf/navigation/nav_grid.hpp>
#include <ogf/sim/ground_truth.hpp>

#include <cstddef>
#include <string>

namespace ogf::eval {

struct NavScores {
  std::size_t truth_free = 0, free_as_free = 0, free_as_occupied = 0;
  std::size_t truth_occupied = 0, occupied_as_occupied = 0, occupied_as_free = 0;

  // Shares of the truth's free (occupied) columns the grid classes free (occupied); 0 with none.
  double freeAsFree() const;
  double freeAsOccupied() const;
  double occupiedAsOccupied() const;
  double occupiedAsFree() const;
  // Scored columns the grid classes as their truth (unknown counts as wrong), and those it classes at all.
  double accuracy() const;
  double coverage() const;
};

NavScores scoreNavGrid(const sim::GroundTruth& truth, const navigation::NavGrid& grid);

// The lines ogf-eval prints under "2-D navigation grid".
std::string navScoreTable(const NavScores& scores, const navigation::NavGrid& grid);

}  // namespace ogf::eval
