// The exports of a map that ogf-map writes beside the map file: every allocated cell as CSV, the occupied
// cells as PLY and PCD, an OctoMap tree, and top-down occupancy and entropy PNGs (formats in
// mapper/formats). Each export is named by the flag that asked for it, so its line says which one failed.
#pragma once

#include <ogf/filter/banded_ogf.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ogf::map_io {

struct MapExports {
  std::string csv, ply, pcd, bt;             // files; empty: not written
  std::string png_dir;                       // folder for occupancy.png and entropy.png; empty: none
  std::optional<double> png_zmin, png_zmax;  // the pictures' height band; default: the walls' band (wallBand)

  bool any() const { return !csv.empty() || !ply.empty() || !pcd.empty() || !bt.empty() || !png_dir.empty(); }
};

// One line about an export: what was written, or (failed) the flag and why it could not be.
struct ExportNote {
  bool failed = false;
  std::string text;  // "--export-csv: x.csv: cannot create CSV file", "x.bt: 12 occupied and 40 free leaves"
};

// Writes every export `exports` asks for, creating their folders; the notes in the order csv, ply, pcd, bt,
// png (an export that is written without a remark has none).
std::vector<ExportNote> writeMapExports(const filter::BandedOgf& map, const MapExports& exports);

// Creates the folder `path` lies in, when it has one (a failure shows when the file is written).
void createParentFolder(const std::string& path);

}  // namespace ogf::map_io
