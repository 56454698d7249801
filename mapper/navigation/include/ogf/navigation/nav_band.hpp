// The height band a 2-D navigation grid is projected from: the slab of the map a ground robot's body sweeps,
// from a little above the floor (so the floor itself, smeared over a cell or two by range noise and the
// filter's kernel, is not an obstacle) to the robot's height. Heights are relative to the floor, which lies
// at floor_z in the map frame (the odometry frame of a ground robot usually has its floor at z = 0).
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>

namespace ogf::navigation {

struct LayerRange {
  std::int32_t lo = 0;  // the lowest and highest cell layer (CellKey z) of the band, inclusive
  std::int32_t hi = -1;
  std::int32_t count() const { return hi >= lo ? hi - lo + 1 : 0; }
  bool contains(std::int32_t z) const { return z >= lo && z <= hi; }
};

struct NavBand {
  double floor_z = 0.0;      // metres, map frame
  double min_height = 0.25;  // metres above the floor
  double max_height = 1.5;
  // A column is free when no cell of the band is occupied and at least this fraction of the band's layers
  // holds a free cell (at least one): occluded or unseen layers make it unknown, not free.
  double min_free_fraction = 0.5;

  // The cell layers whose centre ((z + 0.5) · resolution) lies in [floor_z + min_height, floor_z + max_height].
  LayerRange layers(double resolution) const;
  // How many free layers make a column free.
  std::int32_t freeLayersNeeded(double resolution) const;

  // Error naming the field: heights not finite, min_height ≥ max_height, min_free_fraction outside [0, 1],
  // or a band that holds no layer or more than kMaxLayers at `resolution`.
  Status validate(double resolution) const;

  static constexpr std::int32_t kMaxLayers = 256;
};

}  // namespace ogf::navigation
