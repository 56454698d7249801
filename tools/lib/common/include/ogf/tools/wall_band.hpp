// The height band a top-down picture of a 3-D map shows by default: the one that shows the walls. A top-down
// picture marks a column occupied when any of its cells in the band is, so the band must leave out the floor
// and the ceiling (either would blacken every column) and hold the standing structure.
//
// The rule reads the map's own cells, column by column:
//   - a run of consecutive occupied cells in a column is a horizontal surface (floor, ceiling, table top)
//     when it is at most 0.6 m thick (a floor smeared by range noise and the filter's kernel) and the column
//     has a free cell within 0.2 m above or below it: rays went past it, over a floor or under a ceiling.
//     Any other occupied cell stands up: a ray that meets a wall ends there, none passes above or below it
//     in that column;
//   - a layer holding more surface cells than standing ones is a floor or a ceiling;
//   - the layers between two of them (or the map's ends) form a storey; the band lies in the storey holding
//     the most standing cells and is 1.8 m high (the whole storey when that is lower);
//   - within the storey, each 1.8 m band scores the columns holding standing cells in it; the lowest band
//     within 5 % of the best score wins (low obstacles, table tops among them, stay in the picture).
// The floor need not be the fullest layer nor at z = 0: a sensor near the ceiling sees the ceiling more than
// the floor, a map in the sensor's frame or with an extrinsic puts the floor anywhere, and a static sensor
// sees walls only over a few metres around its own height.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace ogf::tools {

struct ColumnCell {
  std::int32_t z = 0;          // the layer: the cell spans [z, z + 1) × resolution metres
  std::int8_t cell_class = 0;  // -1 free, 0 unknown, +1 occupied
};

struct WallBand {
  std::int32_t lowest_layer = 0;  // the band's layers, inclusive
  std::int32_t highest_layer = 0;
  double z_min =
      0.0;  // metres: the bottom face of the lowest layer and the top face of the highest, so a cell
  double z_max = 0.0;  // is in the band when its centre lies in [z_min, z_max]
  std::string reason;  // why, in a few words ("floor at -1.50 m, ceiling at 1.40 m; 1651 wall columns")
};

class WallBandFinder {
 public:
  static constexpr double kBandHeightM = 1.8;
  static constexpr double kMaxSurfaceThicknessM = 0.6;  // a floor smeared by range noise and the filter
  static constexpr double kFreeReachM = 0.2;       // how far from a surface its free cells are looked for
  static constexpr double kScoreTolerance = 0.05;  // bands this close to the best score count as equal

  explicit WallBandFinder(double resolution_m);

  // One column of the map: its allocated cells in increasing z, at most one per layer.
  void addColumn(std::span<const ColumnCell> cells);

  // nullopt when no column held an occupied cell.
  std::optional<WallBand> band() const;

 private:
  struct Storey {
    std::int32_t lo = 0, hi = 0;  // layers, inclusive
    std::int64_t wall_cells = 0;
  };
  void addStarts(std::map<std::int32_t, std::int64_t>& steps, std::span<const std::int32_t> layers) const;
  WallBand makeBand(std::int32_t lo, std::int32_t hi, std::string reason) const;

  double resolution_;
  std::int32_t band_layers_;
  std::int32_t max_surface_layers_;
  std::int32_t free_reach_layers_;
  std::map<std::int32_t, std::int64_t> wall_cells_;     // layer -> vertical occupied cells
  std::map<std::int32_t, std::int64_t> surface_cells_;  // layer -> horizontal-surface occupied cells
  // Band start layer -> +n/-n: columns with a standing cell in the band of band_layers_ starting there, as
  // steps to sum up to the start.
  std::map<std::int32_t, std::int64_t> wall_column_steps_;
};

// The band a picture draws: the given bounds (--png-zmin, --png-zmax) where set, the walls' band of `source`
// ("the map", "the truth") for the others; one bound alone keeps the walls' other bound when that leaves a
// band, else makes a band the walls' band's height. No walls' band (nothing occupied): every layer.
struct PictureBand {
  double z_min = -1.0e9;  // metres; a cell is in the band when its centre lies in [z_min, z_max]
  double z_max = 1.0e9;
  std::string
      why;  // for the log: "set by --png-zmin and --png-zmax", "the walls' band chosen from the map: ..."
};
PictureBand pictureBand(const std::optional<WallBand>& walls, std::optional<double> z_min,
                        std::optional<double> z_max, std::string_view source);

}  // namespace ogf::tools
