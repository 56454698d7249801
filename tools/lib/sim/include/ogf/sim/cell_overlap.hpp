// How a grid cell meets a solid: not at all, through the solid's surface, or wholly inside it. The ground
// truth is built from this.
//
// Cells are half-open, as in the CellKey convention: cell (i, j, k) is [i·r, (i+1)·r) × [j·r, (j+1)·r) ×
// [k·r, (k+1)·r), the cell floor(p / r) in which a return at p lands. A cell is
//   Surface when it holds a point of the solid's boundary (so a face on a cell boundary belongs to the
//           cell above it, the one floor(p / r) gives a return on that face),
//   Inside  when every point of it lies in the solid's interior,
//   None    when it holds no point of the solid.
// One tolerance: a face whose coordinate, in cells, lies within kOnCellBoundary of a whole number is taken
// to lie on that cell boundary (a wall given as centre 8.1 and size 0.2 starts at 7.999999999999999 in
// floating point; it is meant to start at 8.0). Axis-aligned faces (box faces at a yaw that is a multiple
// of 90°, cylinder ends, axis-aligned half-spaces) are classified exactly after that; the slanted faces of
// a yawed box, a cylinder's side and a tilted half-space, whose meeting a boundary is a matter of chance,
// are tested against the cell with its upper faces moved in by 1e-9 cells.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <array>
#include <optional>
#include <utility>

#include "ogf/sim/shapes.hpp"

namespace ogf::sim {

enum class CellOverlap { None, Surface, Inside };

// In cells: a face this close to a cell boundary lies on it.
inline constexpr double kOnCellBoundary = 1e-6;

// One shape seen on one grid: built once per solid, then asked about each cell.
class CellClassifier {
 public:
  CellClassifier(const Shape& shape, double resolution);

  CellOverlap classify(const CellKey& key) const;

  // The first and last cell, per axis, that can meet the shape; nullopt when it is unbounded.
  std::optional<std::pair<CellKey, CellKey>> keyRange() const;

 private:
  enum class Kind { AxisBox, YawedBox, Cylinder, TiltedHalfSpace };
  Kind kind_ = Kind::AxisBox;
  // In cells. AxisBox: the closed box [lo, hi] per axis, ±infinity where unbounded (an axis-aligned
  // half-space is one). YawedBox and Cylinder: lo/hi on z only.
  std::array<double, 3> lo_{};
  std::array<double, 3> hi_{};
  // YawedBox: footprint centre, half sizes and yaw. Cylinder: centre and radius (half_[0]).
  std::array<double, 2> centre_{};
  std::array<double, 2> half_{};
  double yaw_ = 0.0;
  // TiltedHalfSpace: {u : normal · u <= offset}.
  std::array<double, 3> normal_{};
  double offset_ = 0.0;
};

}  // namespace ogf::sim
