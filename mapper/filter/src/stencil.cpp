// Stencil offsets, forward slots and the covariance pairs of one banded update.
#include "ogf/filter/stencil.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>


namespace ogf::filter {

Stencil::Stencil(int dimensions, StencilShape shape) {
  const int reach = shape.reach();
  const int zReach = dimensions == 3 ? reach : 0;
  for (int x = -reach; x <= reach; ++x) {
    for (int y = -reach; y <= reach; ++y) {
      for (int z = -zReach; z <= zReach; ++z) {
        const CellKey o{x, y, z};
        if (shape.contains(o)) {
          offsets_.push_back(o);
          extent_ = std::max({extent_, std::abs(x), std::abs(y), std::abs(z)});
        }
      }
    }
  }
  for (const CellKey& o : offsets_) {
    if (isForward(o)) {
      forward_.push_back(o);
    }
  }
  for (std::size_t s = 0; s < offsets_.size(); ++s) {
    const CellKey& o = offsets_[s];
    if (o == CellKey{}) {
      self_ = s;
    }
    forwardSlot_.push_back(static_cast<std::int16_t>(forwardIndexOf(o)));
    backwardSlot_.push_back(static_cast<std::int16_t>(forwardIndexOf(CellKey{} - o)));
  }
  // Every stored pair (cell a, cell a + f) with both ends inside the stencil, found through a dense index
  // of the box [-reach, reach]³ so large stencils build in O(cells · forward).
  const int side = 2 * reach + 1;
  std::vector<int> indexOf(static_cast<std::size_t>(side) * static_cast<std::size_t>(side) *
                               static_cast<std::size_t>(2 * zReach + 1),
                           -1);
  const auto boxIndex = [&](const CellKey& o) {
    return static_cast<std::size_t>((o.x + reach) + side * ((o.y + reach) + side * (o.z + zReach)));
  };
  for (std::size_t a = 0; a < offsets_.size(); ++a) {
    indexOf[boxIndex(offsets_[a])] = static_cast<int>(a);
  }
  for (std::size_t a = 0; a < offsets_.size(); ++a) {
    for (std::size_t f = 0; f < forward_.size(); ++f) {
      const CellKey b = offsets_[a] + forward_[f];
      if (std::abs(b.x) > reach || std::abs(b.y) > reach || std::abs(b.z) > zReach) {
        continue;
      }
      const int t = indexOf[boxIndex(b)];
      if (t >= 0) {
        pairs_.push_back({static_cast<std::uint16_t>(a), static_cast<std::uint16_t>(f), static_cast<std::uint16_t>(t)});
      }
    }
  }
}

int Stencil::forwardIndexOf(const CellKey& o) const {
  const auto it = std::find(forward_.begin(), forward_.end(), o);
  return it == forward_.end() ? -1 : static_cast<int>(it - forward_.begin());
}

}  // namespace ogf::filter
