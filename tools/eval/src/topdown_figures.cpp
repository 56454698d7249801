// Top-down figures of truth and maps: see topdown_figures.hpp.
#include "ogf/eval/topdown_figures.hpp"

#include <ogf/sim/ground_truth.hpp>
#include <ogf/tools/image.hpp>
#include <ogf/tools/png_writer.hpp>

#include <algorithm>
#include <functional>

namespace ogf::eval {
namespace {

using tools::Rgb;
constexpr Rgb kOccupied{0, 0, 0};
constexpr Rgb kFree{255, 255, 255};
constexpr Rgb kUnknown{150, 150, 150};
constexpr Rgb kNoData{60, 60, 60};

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

tools::Image canvas(const sim::GroundTruth& t, int scale) { return tools::Image::rgb(t.size[0] * scale, t.size[1] * scale); }

void paint(tools::Image& img, const sim::GroundTruth& t, int scale, int ix, int iy, Rgb c) {
  img.fillRect(ix * scale, (t.size[1] - 1 - iy) * scale, scale, scale, c);  // y up
}

}  // namespace

Status writeTruthPng(const sim::GroundTruth& truth, const HeightBand& band, int scale, const std::filesystem::path& path) {
  auto img = canvas(truth, scale);
  forEachColumn(truth, band, [&](int ix, int iy, std::span<const std::size_t> cells) {
    bool occ = false, fre = false;
    for (auto i : cells) {
      occ |= truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Occupied);
      fre |= truth.cells[i] == static_cast<std::uint8_t>(sim::CellClass::Free);
    }
    paint(img, truth, scale, ix, iy, occ ? kOccupied : (fre ? kFree : kNoData));
  });
  return save(img, path);
}

Status writeMapPngs(const sim::GroundTruth& truth, std::span<const CellEstimate> estimates, const HeightBand& band,
                    int scale, const std::filesystem::path& dir, const std::string& name) {
  auto classes = canvas(truth, scale);
  auto errors = canvas(truth, scale);
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
    paint(classes, truth, scale, ix, iy, occ ? kOccupied : (fre ? kFree : kUnknown));
    if (known == 0) {
      paint(errors, truth, scale, ix, iy, kNoData);
    } else {
      const auto g = static_cast<std::uint8_t>(255 - (255 * wrong) / known);
      paint(errors, truth, scale, ix, iy, Rgb{255, g, g});
    }
  });
  if (auto st = save(classes, dir / (name + "_classes.png")); !st) return st;
  return save(errors, dir / (name + "_errors.png"));
}

}  // namespace ogf::eval
