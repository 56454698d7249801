// The cells a straight ray passes through, in order, by the voxel traversal of Amanatides & Woo, "A Fast
// Voxel Traversal Algorithm for Ray Tracing" (Eurographics 1987): a range-for over ogf::CellKey.
//
//   for (const CellKey cell : RayCaster(origin, endpoint, resolution)) { ... }
//
// What "passes through" means, exactly: cells are half-open boxes as CellKey defines them; a cell is on
// the ray when some point of the closed segment [origin, endpoint] lies in it. The cells come in the
// order the segment enters them. The origin cell comes first; the end cell (cellKeyOf(endpoint)) is left
// out, because the measurement model of Sun et al. (Sec. VI-B) makes it the occupied cell and every other
// cell free. No cell comes twice (a line meets a convex cell in one interval). A zero-length ray, or one
// that stays in one cell, yields nothing.
//
// Ties (the segment crossing an edge or corner of cells exactly) follow from the half-open rule: at the
// crossing, axes stepping up have already changed cell and axes stepping down have not, so the traversal
// steps the upward axes first (one cell, which the segment touches in a single point when downward axes
// are also tied), then the downward ones. Ties are detected exactly whenever the inputs are exact in
// binary (for example coordinates on a 1/16-cell grid at a power-of-two resolution): the crossing
// parameters are kept as t·Dx·Dy·Dz, which A&W's update tMax += tDelta then keeps exact.
//
// Robustness: the number of boundaries to cross on each axis is fixed up front from the origin and end
// cells, so rounding can at worst reorder two nearly simultaneous crossings; the traversal always stops
// at the end cell and never overshoots. Preconditions: finite inputs whose cell coordinates fit int32,
// resolution > 0.
#pragma once

#include <ogf/core/cell_key.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>

namespace ogf::fusion {

// One traversal in progress. An input iterator; compare it with std::default_sentinel for the end.
class RayIterator {
 public:
  using value_type = CellKey;
  using difference_type = std::ptrdiff_t;
  using iterator_concept = std::input_iterator_tag;

  CellKey operator*() const { return {cell_[0], cell_[1], cell_[2]}; }

  [[gnu::always_inline]] RayIterator& operator++() {
    step();
    return *this;
  }
  void operator++(int) { step(); }

  // Cells still to come, counting the current one: exact unless ties merge crossings.
  std::int64_t crossingsLeft() const { return crossings_left_; }

  friend bool operator==(const RayIterator& it, std::default_sentinel_t) { return it.crossings_left_ == 0; }

 private:
  friend class RayCaster;
  friend class CellMarks;  // runs the same traversal with the state in locals (CellMarks::markFree)

  // Everything on the stepping path is forced inline and indexes its arrays with constants only: the
  // traversal is fast when the iterator's state lives in the caller's registers, and slow (state spilled
  // to memory, ~4x) otherwise.
  [[gnu::always_inline]] void step() {
    // A&W's step: advance the axis whose next boundary comes first. Equal crossings (exact ties) take the
    // slower path below.
    if (next_[0] < next_[1]) {
      if (next_[0] < next_[2]) return advance<0>();
      if (next_[2] < next_[0]) return advance<2>();
    } else if (next_[1] < next_[0]) {
      if (next_[1] < next_[2]) return advance<1>();
      if (next_[2] < next_[1]) return advance<2>();
    }
    stepTied();
  }

  // The tie rule from the half-open cells (see the file comment), for crossings `n` of which some are
  // equal, maybe not the smallest: of the axes crossing first, the upward ones step together; the downward
  // ones are then the smallest crossing of the next step. Bit A set: axis A steps. CellMarks::markFree
  // applies the same rule to its own copy of the state.
  [[gnu::always_inline]] static unsigned tiedAxes(double n0, double n1, double n2, std::int32_t s0, std::int32_t s1,
                                                  std::int32_t s2) {
    const double n01 = n1 < n0 ? n1 : n0;
    const double t = n2 < n01 ? n2 : n01;
    const unsigned first = (!(n0 > t) ? 1U : 0U) | (!(n1 > t) ? 2U : 0U) | (!(n2 > t) ? 4U : 0U);
    const unsigned up = first & ((s0 > 0 ? 1U : 0U) | (s1 > 0 ? 2U : 0U) | (s2 > 0 ? 4U : 0U));
    return up != 0 ? up : first;
  }

  [[gnu::always_inline]] void stepTied() {
    const unsigned axes = tiedAxes(next_[0], next_[1], next_[2], step_[0], step_[1], step_[2]);
    if ((axes & 1U) != 0) advance<0>();
    if ((axes & 2U) != 0) advance<1>();
    if ((axes & 4U) != 0) advance<2>();
  }

  template <std::size_t A>
  [[gnu::always_inline]] void advance() {
    cell_[A] += step_[A];
    --crossings_left_;
    if (--left_[A] == 0) {
      next_[A] = kNever;  // no boundary left on this axis: it never wins again
    } else {
      next_[A] += delta_[A];
    }
  }

  static constexpr double kNever = std::numeric_limits<double>::infinity();

  std::array<std::int32_t, 3> cell_{};
  std::array<std::int32_t, 3> step_{};
  // Scaled ray parameter (t · |Dx·Dy·Dz| over the axes that move) of the next boundary on each axis, and
  // its increment per cell (A&W's tMax and tDelta, scaled so both stay exact for exact inputs).
  std::array<double, 3> next_{kNever, kNever, kNever};
  std::array<double, 3> delta_{};
  std::array<std::int64_t, 3> left_{};  // boundaries still to cross per axis
  std::int64_t crossings_left_ = 0;     // boundaries still to cross on all axes
};

// The range of cells from origin (included) to endpoint (excluded), metres in the map frame.
class RayCaster {
 public:
  RayCaster(const Eigen::Vector3d& origin, const Eigen::Vector3d& endpoint, double resolution);

  RayIterator begin() const { return first_; }
  std::default_sentinel_t end() const { return {}; }

  CellKey originCell() const { return *first_; }
  CellKey endCell() const { return end_cell_; }
  // An upper bound on the number of cells the range yields (exact unless the ray crosses edges exactly).
  std::int64_t maxCells() const { return first_.crossingsLeft(); }

 private:
  RayIterator first_;
  CellKey end_cell_;
};

}  // namespace ogf::fusion
