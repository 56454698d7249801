#include "ogf/map_io/map_exports.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <ogf/tools/wall_band.hpp>
#include <system_error>

#include "ogf/map_formats/cell_csv.hpp"
#include "ogf/map_formats/cell_pcd.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_formats/nav_map_files.hpp"
#include "ogf/map_formats/octomap_export.hpp"
#include "ogf/map_io/topdown_png.hpp"

namespace ogf::map_io {
namespace {

namespace mf = map_formats;

void noteFailure(std::vector<ExportNote>& notes, const char* flag, const Status& st) {
  if (!st) notes.push_back({true, std::string(flag) + ": " + st.error().message});
}

void writeOctomap(const mf::MapCells& cells, const std::string& path, std::vector<ExportNote>& notes) {
  auto bt = mf::writeOctomapBinary(cells, path);
  if (!bt) {
    noteFailure(notes, "--export-bt", bt.error());
    return;
  }
  notes.push_back(
      {false, fmt::format("{}: {} occupied and {} free leaves{}", path, bt->occupied, bt->free,
                          bt->out_of_range > 0
                              ? fmt::format(", {} cells beyond OctoMap's extent left out", bt->out_of_range)
                              : std::string())});
}

void writePictures(const mf::MapCells& cells, const MapExports& e, std::vector<ExportNote>& notes) {
  const auto band = tools::pictureBand(wallBand(cells), e.png_zmin, e.png_zmax, "the map");
  auto png = writeTopDownPngs(cells, {band.z_min, band.z_max}, e.png_dir);
  if (!png) {
    noteFailure(notes, "--png", png.error());
    return;
  }
  notes.push_back(
      {false, fmt::format("{}: occupancy.png and entropy.png of {} x {} cell columns, z {:.2f} to "
                          "{:.2f} m ({})",
                          e.png_dir, png->width, png->height, band.z_min, band.z_max, band.why)});
}

void writeNavGrid(const mf::MapCells& cells, const MapExports& e, std::vector<ExportNote>& notes) {
  const auto mode = mf::parseNavImageMode(e.nav_mode);
  if (!mode) return noteFailure(notes, "--nav-mode", mode.error());
  const auto band = e.navBand();
  auto grid = mf::projectCells(cells, band);
  if (!grid) return noteFailure(notes, "--export-nav", grid.error());
  auto files = mf::writeNavMap(*grid, e.nav_dir, *mode);
  if (!files) return noteFailure(notes, "--export-nav", files.error());
  const auto layers = band.layers(cells.resolution);
  notes.push_back({false, fmt::format("{}: map.pgm and map.yaml ({}), {} x {} columns of {} m from ({:.2f}, {:.2f}) m: "
                                      "{} free, {} occupied, {} unknown; band {:.2f} to {:.2f} m above the floor at "
                                      "z = {:.2f} m ({} cell layers)",
                                      e.nav_dir, mf::toString(*mode), grid->width, grid->height, grid->resolution,
                                      grid->originX(), grid->originY(), files->free, files->occupied, files->unknown,
                                      band.min_height, band.max_height, band.floor_z, layers.count())});
}

}  // namespace

navigation::NavBand MapExports::navBand() const {
  auto band = nav_band;
  if (nav_floor_z) band.floor_z = *nav_floor_z;
  if (nav_min_height) band.min_height = *nav_min_height;
  if (nav_max_height) band.max_height = *nav_max_height;
  if (nav_min_free_fraction) band.min_free_fraction = *nav_min_free_fraction;
  return band;
}

void createParentFolder(const std::string& path) {
  const auto parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!path.empty() && !parent.empty()) std::filesystem::create_directories(parent, ec);
}

std::vector<ExportNote> writeMapExports(const filter::BandedOgf& map, const MapExports& e) {
  std::vector<ExportNote> notes;
  if (!e.any()) return notes;
  for (const std::string* path : {&e.csv, &e.ply, &e.pcd, &e.bt}) createParentFolder(*path);
  const mf::MapCells cells = mf::collectCells(map);
  if (!e.csv.empty()) noteFailure(notes, "--export-csv", mf::writeCellCsv(cells, e.csv));
  if (!e.ply.empty()) noteFailure(notes, "--export-ply", mf::writeOccupiedPly(cells, e.ply));
  if (!e.pcd.empty()) noteFailure(notes, "--export-pcd", mf::writeOccupiedPcd(cells, e.pcd));
  if (!e.bt.empty()) writeOctomap(cells, e.bt, notes);
  if (!e.png_dir.empty()) writePictures(cells, e, notes);
  if (!e.nav_dir.empty()) writeNavGrid(cells, e, notes);
  return notes;
}

}  // namespace ogf::map_io
