// What an OGF says about a cell, in the form the scores take: its class by eq. (3) of Sun et al. and its
// predictive probability of occupancy (filter::queryCell; a cell the map never allocated is unknown, 0.5).
#pragma once

#include <ogf/core/cell_key.hpp>
#include <ogf/filter/banded_ogf.hpp>

#include "ogf/eval/map_scores.hpp"

namespace ogf::eval {

CellEstimate ogfEstimate(const filter::BandedOgf& map, const CellKey& key);

}  // namespace ogf::eval
