// How a grid cell meets a solid: not at all, through the solid's surface, or wholly inside it. The ground
// truth is built from this; each test is exact for its shape (corner tests for convexity, separating axes
// for boxes, nearest point for cylinders).
#pragma once

#include "ogf/sim/shapes.hpp"
#include "ogf/sim/world.hpp"

namespace ogf::sim {

enum class CellOverlap { None, Surface, Inside };

// `cell` is the closed box of a grid cell shrunk by a hair on its upper faces, which makes the result the
// one for the half-open cell [min, max) of the CellKey convention: a surface lying exactly on a cell
// boundary belongs to the cell above it, as floor(p / r) assigns a point on it.
CellOverlap classifyCell(const Shape& shape, const Aabb& cell);

}  // namespace ogf::sim
