#include "ogf/navigation/nav_grid.hpp"

#include <algorithm>

namespace ogf::navigation {
namespace {

// splitmix64's finaliser: every input bit affects every output bit.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

std::uint64_t columnChecksum(const ColumnKey& key, const NavColumn& column) {
  std::uint64_t h = mix(static_cast<std::uint32_t>(key.x));
  h = mix(h ^ static_cast<std::uint32_t>(key.y));
  return mix(h ^ (static_cast<std::uint64_t>(static_cast<std::uint8_t>(column.cost)) |
                  static_cast<std::uint64_t>(static_cast<std::uint8_t>(column.column_class)) << 8));
}

NavColumn NavGrid::at(const ColumnKey& key) const {
  const auto col = key.x - origin.x;
  const auto row = key.y - origin.y;
  if (col < 0 || row < 0 || col >= width || row >= height) return {};
  const auto i = index(col, row);
  return {cost[i], column_class[i]};
}

std::size_t NavGrid::knownColumns() const {
  return static_cast<std::size_t>(
      std::count_if(column_class.begin(), column_class.end(), [](std::int8_t c) { return c != kClassUnknown; }));
}

std::uint64_t NavGrid::checksum() const {
  std::uint64_t sum = 0;
  for (std::int32_t row = 0; row < height; ++row) {
    for (std::int32_t col = 0; col < width; ++col) {
      const auto i = index(col, row);
      if (column_class[i] == kClassUnknown) continue;
      sum += columnChecksum({origin.x + col, origin.y + row}, {cost[i], column_class[i]});
    }
  }
  return sum;
}

}  // namespace ogf::navigation
