// A 2-D navigation grid as a planner reads it: a dense rectangle of columns over the known part of the map,
// row 0 the southernmost (lowest y), as a ROS OccupancyGrid and the map_server PGM's bottom row.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ogf/navigation/column_rule.hpp"
#include "ogf/navigation/nav_band.hpp"

namespace ogf::navigation {

struct ColumnKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  friend constexpr bool operator==(const ColumnKey&, const ColumnKey&) = default;
  friend constexpr auto operator<=>(const ColumnKey&, const ColumnKey&) = default;
};

// The checksum term of one known column: a 64-bit hash of (x, y, cost, class). A grid's checksum is the
// wrapping sum of its known columns' terms (unknown columns add nothing), so it does not depend on order
// and follows each change.
std::uint64_t columnChecksum(const ColumnKey& key, const NavColumn& column);

struct NavGrid {
  double resolution = 0.2;
  NavBand band;
  ColumnKey origin;        // the south-west column, row 0 column 0
  std::int32_t width = 0;  // columns along x
  std::int32_t height = 0; // rows along y
  std::vector<std::int8_t> cost;          // width × height, row-major from row 0; kUnknownCost unknown
  std::vector<std::int8_t> column_class;  // kClass* values

  std::size_t index(std::int32_t col, std::int32_t row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(col);
  }
  // The column (x, y) of the map; unknown outside the rectangle.
  NavColumn at(const ColumnKey& key) const;
  // Metres of the south-west corner of column `origin` (the map_server YAML's origin).
  double originX() const { return origin.x * resolution; }
  double originY() const { return origin.y * resolution; }
  std::size_t knownColumns() const;
  std::uint64_t checksum() const;
};

}  // namespace ogf::navigation
