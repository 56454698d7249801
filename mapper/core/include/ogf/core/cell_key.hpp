// The integer address of a grid cell, shared by every mapping layer (filter, fusion, deltas, files).
// Cell (i, j, k) at resolution r covers [i*r, (i+1)*r) x [j*r, (j+1)*r) x [k*r, (k+1)*r) in the map frame;
// its centre is ((i+0.5)*r, ...). This is the convention of map_delta_t's key_x/key_y/key_z.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace ogf {

struct CellKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;

  friend constexpr bool operator==(const CellKey&, const CellKey&) = default;
  // Lexicographic (x, then y, then z): the deterministic order used wherever order matters.
  friend constexpr auto operator<=>(const CellKey&, const CellKey&) = default;

  constexpr CellKey operator+(const CellKey& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr CellKey operator-(const CellKey& o) const { return {x - o.x, y - o.y, z - o.z}; }
};

// The cell containing point p (metres, map frame) at `resolution` metres per cell. Floors, so negative
// coordinates map to negative keys without a seam at 0.
inline CellKey cellKeyOf(const Eigen::Vector3d& p, double resolution) {
  return {static_cast<std::int32_t>(std::floor(p.x() / resolution)),
          static_cast<std::int32_t>(std::floor(p.y() / resolution)),
          static_cast<std::int32_t>(std::floor(p.z() / resolution))};
}

// Centre of a cell, metres.
inline Eigen::Vector3d cellCentre(const CellKey& k, double resolution) {
  return {(k.x + 0.5) * resolution, (k.y + 0.5) * resolution, (k.z + 0.5) * resolution};
}

// A well-mixing hash (the three coordinates folded through a 64-bit multiply-xorshift), for hashed
// containers of cells or blocks.
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const noexcept {
    std::uint64_t h = static_cast<std::uint32_t>(k.x);
    h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint32_t>(k.y);
    h = h * 0x9E3779B97F4A7C15ULL ^ static_cast<std::uint32_t>(k.z);
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 29;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace ogf
