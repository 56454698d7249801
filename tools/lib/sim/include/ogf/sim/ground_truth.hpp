// The true occupancy of a simulated world on a grid (the CellKey convention of ogf/core/cell_key.hpp:
// cell (i, j, k) covers [i·r, (i+1)·r) × [j·r, (j+1)·r) × [k·r, (k+1)·r)), what ogf-eval scores maps
// against, and its file format.
//
// Classes: occupied = the cell holds part of a solid's surface; unobservable = the cell lies wholly inside
// a solid, or is open air sealed off from every sensor position by surfaces (behind a wall: no beam can
// reach it); free = open air (touching no solid) that the sensor's air space reaches. Free does not mean
// a beam of this particular run crossed the cell. A cell inside the union of two overlapping solids but
// inside neither alone counts as occupied.
//
// File (truth.grid): a text header of "key value" lines, then the raw cells.
//   OGF-TRUTH 1
//   resolution 0.2                      metres per cell edge
//   min_key -2 -2 -2                    CellKey of the first cell
//   size 54 44 19                       cells along x, y, z
//   classes 0=free 1=occupied 2=unobservable
//   order x-fastest                     byte index = ix + nx·(iy + ny·iz), i = key − min_key
//   fnv1a64 0123456789abcdef            FNV-1a 64 of the cell bytes, hex
//   data
// followed by exactly nx·ny·nz bytes, one class per cell, and nothing after.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/sim/world.hpp"

namespace ogf::sim {

enum class CellClass : std::uint8_t { Free = 0, Occupied = 1, Unobservable = 2 };

struct GroundTruth {
  double resolution = 0.2;
  CellKey min_key;
  std::array<std::int32_t, 3> size{0, 0, 0};
  std::vector<std::uint8_t> cells;  // CellClass values, x fastest

  // The class of a cell, nullopt outside the grid.
  std::optional<CellClass> at(const CellKey& key) const;
  std::size_t count(CellClass c) const;
  CellKey keyOf(std::size_t index) const;
};

// Classifies every cell whose box meets world.bounds. `sensor_positions` (world frame) seed the open air
// the sensor can reach: open-air cells not face-connected to a seed's cell through open air become
// unobservable. With no positions every open-air cell is free.
GroundTruth computeGroundTruth(const World& world, double resolution,
                               const std::vector<Eigen::Vector3d>& sensor_positions = {});

// The cells of `grid` that a moving solid of the world met at some instant of [0, duration_s], sampled every
// step_s: Occupied (1) for those, Free (0) for the rest; the same grid geometry, so it is written and read
// as a truth grid (swept.grid). What a map still holds there at the end is what the solid left behind.
GroundTruth sweptCells(const World& world, const GroundTruth& grid, double duration_s, double step_s = 0.01);

// FNV-1a 64 of the cell bytes, as the file header states it.
std::uint64_t truthChecksum(const std::vector<std::uint8_t>& cells);

Status writeGroundTruth(const std::string& path, const GroundTruth& truth);
// Refuses a wrong magic or version, a missing or malformed header line (named), a size that does not
// match the data, trailing bytes, a checksum mismatch or a byte that is no class.
Result<GroundTruth> readGroundTruth(const std::string& path);

}  // namespace ogf::sim
