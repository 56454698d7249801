// The neighbourhood one measurement touches in the banded filter: every cell offset o with |o| ≤ R (a ball
// in 3-D, a disc in the z = 0 plane in 2-D), the "forward" half of it under which a cell stores its
// covariances (the other half is stored by the neighbour, by symmetry), and the precomputed list of stored
// covariance pairs inside the neighbourhood that the rank-1 update of eq. (5) changes.
#pragma once

#include <ogf/core/cell_key.hpp>

#include "ogf/filter/stencil_shape.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace ogf::filter {

// Lexicographically positive: z > 0, or z = 0 and y > 0, or z = y = 0 and x > 0.
constexpr bool isForward(const CellKey& o) {
  return o.z > 0 || (o.z == 0 && (o.y > 0 || (o.y == 0 && o.x > 0)));
}

// A stored covariance between stencil cells `from` and `to` = from + forwardOffsets()[forward], kept by
// `from`.
struct StencilPair {
  std::uint16_t from = 0;
  std::uint16_t forward = 0;
  std::uint16_t to = 0;
};

class Stencil {
 public:
  Stencil(int dimensions, StencilShape shape);

  // Every offset of the shape, including 0, in lexicographic (x, y, z) order.
  std::span<const CellKey> offsets() const { return offsets_; }
  // The forward half, in lexicographic order: the covariances a cell stores, one slot each.
  std::span<const CellKey> forwardOffsets() const { return forward_; }
  std::size_t selfIndex() const { return self_; }
  // For offsets()[s]: the forward slot of o if o is forward, else -1.
  std::span<const std::int16_t> forwardSlot() const { return forwardSlot_; }
  // For offsets()[s]: the forward slot of −o if o is backward (stored by the neighbour), else -1.
  std::span<const std::int16_t> backwardSlot() const { return backwardSlot_; }
  std::span<const StencilPair> pairs() const { return pairs_; }
  // Largest |component| of any offset: how far past its block a measurement reaches.
  int extent() const { return extent_; }
  // Forward slot of an offset, or -1 when it is not a forward offset of the stencil.
  int forwardIndexOf(const CellKey& o) const;

 private:
  std::vector<CellKey> offsets_;
  std::vector<CellKey> forward_;
  std::vector<std::int16_t> forwardSlot_;
  std::vector<std::int16_t> backwardSlot_;
  std::vector<StencilPair> pairs_;
  std::size_t self_ = 0;
  int extent_ = 0;
};

}  // namespace ogf::filter
