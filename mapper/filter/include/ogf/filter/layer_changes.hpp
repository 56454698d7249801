// Which cells of one z layer of a block (64 cells, compact storage) an update changed: the change
// detection copies each touched layer's means and variance codes before the batch and compares the copy
// with the block after it, a layer at a time in vectors; only the cells that changed are then read one
// by one.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ogf::filter {

inline constexpr std::size_t kLayerCells = 64;

// Bit j set when cell j's mean or variance code differs between the two copies (a, b). Means compare as
// floats, as the cell-by-cell detection did: +0 equals −0, and a NaN always differs.
using LayerChanges = std::uint64_t (*)(const float* meansA, const std::uint16_t* codesA, const float* meansB,
                                       const std::uint16_t* codesB);

// The same bits on every CPU: in 256-bit vectors when `avx2`, else one cell at a time.
LayerChanges layerChangesFor(bool avx2);

}  // namespace ogf::filter
