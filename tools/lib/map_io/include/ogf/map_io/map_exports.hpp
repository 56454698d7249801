// The exports of a map that ogf-map writes beside the map file: every allocated cell as CSV, the occupied
// cells as PLY and PCD, an OctoMap tree, top-down occupancy and entropy PNGs, and the 2-D navigation grid as
// map_server's map.pgm and map.yaml (formats in mapper/formats). Each export is named by the flag that asked for it, so its line says which one failed.
#pragma once

#include <ogf/filter/banded_ogf.hpp>
#include <ogf/navigation/nav_band.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ogf::map_io {

struct MapExports {
  std::string csv, ply, pcd, bt;             // files; empty: not written
  std::string png_dir;                       // folder for occupancy.png and entropy.png; empty: none
  std::optional<double> png_zmin, png_zmax;  // the pictures' height band; default: the walls' band (wallBand)
  std::string nav_dir;                       // folder for map.pgm and map.yaml; empty: none
  navigation::NavBand nav_band;              // the --config file's nav.* band (the defaults without one)
  // The --nav-* flags given, over nav_band.
  std::optional<double> nav_floor_z, nav_min_height, nav_max_height, nav_min_free_fraction;
  std::string nav_mode = "trinary";          // trinary | scale

  bool any() const {
    return !csv.empty() || !ply.empty() || !pcd.empty() || !bt.empty() || !png_dir.empty() || !nav_dir.empty();
  }
  // nav_band with the flags given applied.
  navigation::NavBand navBand() const;
};

// One line about an export: what was written, or (failed) the flag and why it could not be.
struct ExportNote {
  bool failed = false;
  std::string text;  // "--export-csv: x.csv: cannot create CSV file", "x.bt: 12 occupied and 40 free leaves"
};

// Writes every export `exports` asks for, creating their folders; the notes in the order csv, ply, pcd, bt,
// png, nav (an export that is written without a remark has none).
std::vector<ExportNote> writeMapExports(const filter::BandedOgf& map, const MapExports& exports);

// Creates the folder `path` lies in, when it has one (a failure shows when the file is written).
void createParentFolder(const std::string& path);

}  // namespace ogf::map_io
