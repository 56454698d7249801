// Every allocated cell of a banded OGF as the delta stream publishes it (quantised predictive probability,
// class by the filter's thresholds, variance), in the filter's cell order: the daemon's first keyframe after
// a restart, exports, and a viewer showing a saved map.
#pragma once

#include <ogf/filter/banded_ogf.hpp>

#include <span>
#include <vector>

#include "ogf/delta/delta_stream.hpp"
#include "ogf/delta/published_cell.hpp"

namespace ogf::pipeline {

std::vector<delta::PublishedCell> publishedCellsOf(const filter::BandedOgf& filter);

// The allocated cells of the published map's slabs (PublishedBlock's 8 × 8 × 1) `slabs`, as above. A cell
// not allocated (never measured, or its region paged out) is left out.
std::vector<delta::PublishedCell> publishedCellsInSlabs(const filter::BandedOgf& filter, std::span<const CellKey> slabs);

// Reads the stream's stale slabs that its waiting set has room for from the filter and hands their cells
// to it (DeltaStream::staleSlabsToRead, refreshStale): after a scan is applied, before its update.
void refreshStaleSlabs(const filter::BandedOgf& filter, delta::DeltaStream& stream);

}  // namespace ogf::pipeline
