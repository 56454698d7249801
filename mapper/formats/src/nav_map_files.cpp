#include "ogf/map_formats/nav_map_files.hpp"

#include <fmt/format.h>
#include <ogf/navigation/nav_projection.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace ogf::map_formats {
namespace {

namespace nav = navigation;

constexpr std::uint8_t kOccupiedPixel = 0;
constexpr std::uint8_t kFreePixel = 254;
constexpr std::uint8_t kUnknownPixel = 205;

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

Status writeAll(const std::filesystem::path& path, std::string_view kind, const std::string& head,
                const std::vector<std::uint8_t>& body) {
  File f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) return Error::system(fmt::format("{}: cannot create {}", path.string(), kind));
  if (std::fwrite(head.data(), 1, head.size(), f.get()) != head.size() ||
      (!body.empty() && std::fwrite(body.data(), 1, body.size(), f.get()) != body.size()) ||
      std::fclose(f.release()) != 0)
    return Error::system(fmt::format("{}: write failed", path.string()));
  return okStatus();
}

}  // namespace

Result<NavImageMode> parseNavImageMode(std::string_view text) {
  if (text == "trinary") return NavImageMode::kTrinary;
  if (text == "scale") return NavImageMode::kScale;
  return Error::usage(fmt::format("'{}': the picture's mode is trinary or scale", text));
}

std::string_view toString(NavImageMode mode) { return mode == NavImageMode::kScale ? "scale" : "trinary"; }

Result<nav::NavGrid> projectCells(const MapCells& cells, const nav::NavBand& band) {
  auto projection = nav::NavProjection::create(cells.resolution, band);
  if (!projection) return projection.error();
  for (const CellRecord& c : cells.cells) projection->update({c.key, c.probability, c.cell_class, c.variance});
  projection->refresh();
  return projection->grid();
}

std::uint8_t navPixel(const nav::NavColumn& column, NavImageMode mode) {
  if (!column.known()) return kUnknownPixel;
  // 255 - round(2.55 · cost), in integers so that a half rounds up whatever the floating point does.
  if (mode == NavImageMode::kScale) return static_cast<std::uint8_t>(255 - (255 * column.cost + 50) / 100);
  return column.column_class == nav::kClassOccupied ? kOccupiedPixel : kFreePixel;
}

Result<NavMapFiles> writeNavMap(const nav::NavGrid& grid, const std::filesystem::path& dir, NavImageMode mode) {
  if (grid.width <= 0 || grid.height <= 0)
    return Error::inputDamaged(fmt::format("{}: no column of the map is known in the band: nothing to draw", dir.string()));
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error::system(fmt::format("{}: cannot create the folder", dir.string()), ec);
  NavMapFiles out{dir / "map.pgm", dir / "map.yaml"};
  std::vector<std::uint8_t> pixels;
  pixels.reserve(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height));
  // The picture's first row is the grid's last (northernmost): a loader puts the last row at the bottom.
  for (std::int32_t row = grid.height - 1; row >= 0; --row) {
    for (std::int32_t col = 0; col < grid.width; ++col) {
      const auto i = grid.index(col, row);
      const nav::NavColumn c{grid.cost[i], grid.column_class[i]};
      pixels.push_back(navPixel(c, mode));
      (c.column_class == nav::kClassOccupied ? out.occupied : c.column_class == nav::kClassFree ? out.free : out.unknown)++;
    }
  }
  const std::string head = fmt::format("P5\n# ogf 2-D navigation grid, {} m, band {:.2f} to {:.2f} m above z = {:.2f} m\n{} {}\n255\n",
                                       grid.resolution, grid.band.min_height, grid.band.max_height, grid.band.floor_z,
                                       grid.width, grid.height);
  if (auto st = writeAll(out.pgm, "PGM file", head, pixels); !st) return st.error();
  const bool scale = mode == NavImageMode::kScale;
  const std::string yaml = fmt::format(
      "image: map.pgm\nmode: {}\nresolution: {}\norigin: [{}, {}, 0.0]\nnegate: 0\noccupied_thresh: {}\nfree_thresh: {}\n",
      toString(mode), grid.resolution, grid.originX(), grid.originY(), scale ? "1.0" : "0.65", scale ? "0.0" : "0.196");
  if (auto st = writeAll(out.yaml, "YAML file", yaml, {}); !st) return st.error();
  return out;
}

}  // namespace ogf::map_formats
