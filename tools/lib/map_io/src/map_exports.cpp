#include "ogf/map_io/map_exports.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <ogf/tools/wall_band.hpp>
#include <system_error>

#include "ogf/map_formats/cell_csv.hpp"
#include "ogf/map_formats/cell_pcd.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_formats/map_cells.hpp"
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

}  // namespace

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
  return notes;
}

}  // namespace ogf::map_io
