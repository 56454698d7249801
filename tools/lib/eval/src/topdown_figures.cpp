// Top-down figures of truth and maps: see topdown_figures.hpp.
#include "ogf/eval/topdown_figures.hpp"

#include <ogf/sim/ground_truth.hpp>
#include <ogf/tools/image.hpp>
#include <ogf/tools/map_figure.hpp>
#include <ogf/tools/png_writer.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <cmath>
#include <vector>

namespace ogf::eval {
namespace {

using tools::Rgb;
constexpr Rgb kOccupied{25, 25, 25};
constexpr Rgb kFree{255, 255, 255};
constexpr Rgb kUnknown{150, 175, 215};
constexpr Rgb kNoData{215, 215, 215};

// Calls `column(ix, iy, cells)` with the truth indices of the column's cells in the band.
void forEachColumn(const sim::GroundTruth& t, const HeightBand& band,
                   const std::function<void(int, int, std::span<const std::size_t>)>& column) {
  const int nx = t.size[0], ny = t.size[1], nz = t.size[2];
  std::vector<std::size_t> cells;
  for (int iy = 0; iy < ny; ++iy) {
    for (int ix = 0; ix < nx; ++ix) {
      cells.clear();
      for (int iz = 0; iz < nz; ++iz) {
        const double centre = (t.min_key.z + iz + 0.5) * t.resolution;
        if (centre < band.z_min || centre > band.z_max) continue;
        cells.push_back(static_cast<std::size_t>(ix) +
                        static_cast<std::size_t>(nx) * (static_cast<std::size_t>(iy) + static_cast<std::size_t>(ny) * static_cast<std::size_t>(iz)));
      }
      column(ix, iy, cells);
    }
  }
}

Status save(const tools::Image& img, const std::filesystem::path& path) {
  std::string error;
  if (!tools::writePng(path, img, error)) return Error{error};
  return okStatus();
}

tools::MapRaster canvas(const sim::GroundTruth& t) {
  const auto n = static_cast<std::size_t>(t.size[0]) * static_cast<std::size_t>(t.size[1]);
  return {t.size[0], t.size[1], std::vector<Rgb>(n, kNoData), t.resolution, t.min_key.x * t.resolution,
          t.min_key.y * t.resolution};
}

void paint(tools::MapRaster& r, int ix, int iy, Rgb c) {
  r.cells[static_cast<std::size_t>(r.height - 1 - iy) * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(ix)] = c;  // y up
}

Rgb errorColour(double share) {
  const auto g = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - std::clamp(share, 0.0, 1.0))));
  return Rgb{255, g, g};
}

std::string bandNote(const sim::GroundTruth& t, const HeightBand& band) {
  return fmt::format("top-down, cells with centres in z {:.2f} to {:.2f} m; {} m cells", band.z_min, band.z_max,
                     t.resolution);
}

}  // namespace

std::optional<tools::WallBand> wallBand(const sim::GroundTruth& truth) {
  tools::WallBandFinder finder(truth.resolution);
  const int nx = truth.size[0], ny = truth.size[1], nz = truth.size[2];
  const std::size_t layer = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  std::vector<tools::ColumnCell> column;
  for (std::size_t xy = 0; xy < layer; ++xy) {
    column.clear();
    for (int iz = 0; iz < nz; ++iz) {
      const auto c = static_cast<sim::CellClass>(truth.cells[xy + layer * static_cast<std::size_t>(iz)]);
      if (c == sim::CellClass::Unobservable) continue;
      column.push_back({truth.min_key.z + iz, static_cast<std::int8_t>(c == sim::CellClass::Occupied ? 1 : -1)});
    }
    finder.addColumn(column);
  }
  return finder.band();
}

Status writeTruthPng(const sim::GroundTruth& truth, const HeightBand& band, int scale, const std::filesystem::path& path) {
  auto img = canvas(truth);
  forEachColumn(truth, band, [&](int ix, int iy, std::span<const std::size_t> cells) {
    bool occ = false, fre = false;
    for (auto i : cells) {
      occ |= truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Occupied);
      fre |= truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Free);
    }
    paint(img, ix, iy, occ ? kOccupied : (fre ? kFree : kNoData));
  });
  tools::FigureKey key;
  key.legend = {{kOccupied, "occupied"}, {kFree, "free"}, {kNoData, "unobservable"}};
  return save(tools::composeMapFigure(img, "Ground truth", bandNote(truth, band), key, scale), path);
}

Status writeMapPngs(const sim::GroundTruth& truth, std::span<const CellEstimate> estimates, const HeightBand& band,
                    int scale, const std::filesystem::path& dir, const std::string& name) {
  auto classes = canvas(truth);
  auto errors = canvas(truth);
  forEachColumn(truth, band, [&](int ix, int iy, std::span<const std::size_t> cells) {
    bool occ = false, fre = false;
    int known = 0, wrong = 0;
    for (auto i : cells) {
      const auto c = estimates[i].cell_class;
      occ |= c > 0;
      fre |= c < 0;
      const auto t = truth.cells[i];
      if (t == static_cast<std::uint8_t>(sim::CellClass::Unobservable)) continue;
      ++known;
      const bool right = (t == static_cast<std::uint8_t>(sim::CellClass::Occupied)) ? c > 0 : c < 0;
      if (!right) ++wrong;
    }
    paint(classes, ix, iy, occ ? kOccupied : (fre ? kFree : kUnknown));
    paint(errors, ix, iy, known == 0 ? kNoData : errorColour(static_cast<double>(wrong) / known));
  });
  tools::FigureKey classKey;
  classKey.legend = {{kOccupied, "occupied"}, {kFree, "free"}, {kUnknown, "unknown"}};
  tools::FigureKey errorKey;
  errorKey.legend = {{kNoData, "no known truth cell"}};
  errorKey.colour_bar = tools::ColourBar{errorColour, "0 (all right)", "1 (all wrong)", "share wrong"};
  const std::string note = bandNote(truth, band);
  const std::string shown = name == "ogf" ? "OGF" : name == "octomap" ? "OctoMap" : name;
  if (auto st = save(tools::composeMapFigure(classes, shown + ": classes", note, classKey, scale),
                     dir / (name + "_classes.png"));
      !st)
    return st;
  return save(tools::composeMapFigure(errors, shown + ": errors against the truth (eq. 13)", note, errorKey, scale),
              dir / (name + "_errors.png"));
}

}  // namespace ogf::eval
