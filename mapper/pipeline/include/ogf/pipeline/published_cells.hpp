// Every allocated cell of a banded OGF as the delta stream publishes it (quantised predictive probability,
// class by the filter's thresholds, variance), in the filter's cell order: the daemon's first keyframe after
// a restart, exports, and a viewer showing a saved map.
#pragma once

#include <ogf/filter/banded_ogf.hpp>

#include <vector>

#include "ogf/delta/published_cell.hpp"

namespace ogf::pipeline {

std::vector<delta::PublishedCell> publishedCellsOf(const filter::BandedOgf& filter);

}  // namespace ogf::pipeline
