// Top-down figures of a map: see topdown_png.hpp.
#include "ogf/map_io/topdown_png.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ogf/filter/occupancy.hpp>
#include <ogf/tools/map_figure.hpp>
#include <ogf/tools/png_writer.hpp>
#include <string>
#include <tuple>
#include <vector>

namespace ogf::map_io {
namespace {

constexpr int kMaxSide = 16384;
constexpr tools::Rgb kOccupied{25, 25, 25};
constexpr tools::Rgb kFree{255, 255, 255};
constexpr tools::Rgb kUnknown{150, 175, 215};
constexpr tools::Rgb kNotObserved{215, 215, 215};

}  // namespace

std::optional<tools::WallBand> wallBand(const map_formats::MapCells& cells) {
  // The cells column by column, each column's from the bottom up.
  std::vector<const map_formats::CellRecord*> order(cells.cells.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = &cells.cells[i];
  std::sort(order.begin(), order.end(),
            [](const map_formats::CellRecord* a, const map_formats::CellRecord* b) {
              return std::tie(a->key.x, a->key.y, a->key.z) < std::tie(b->key.x, b->key.y, b->key.z);
            });
  tools::WallBandFinder finder(cells.resolution);
  std::vector<tools::ColumnCell> column;
  for (std::size_t i = 0; i < order.size(); ++i) {
    column.push_back({order[i]->key.z, order[i]->cell_class});
    const bool last = i + 1 == order.size() || order[i + 1]->key.x != order[i]->key.x ||
                      order[i + 1]->key.y != order[i]->key.y;
    if (last) {
      finder.addColumn(column);
      column.clear();
    }
  }
  return finder.band();
}

Result<TopDownSize> writeTopDownPngs(const map_formats::MapCells& cells, const TopDownBand& band,
                                     const std::filesystem::path& dir, const std::optional<TopDownArea>& area) {
  const auto inBand = [&](const map_formats::CellRecord& c) {
    const double z = (c.key.z + 0.5) * cells.resolution;
    const bool inside = !area || (c.key.x >= area->x0 && c.key.x <= area->x1 && c.key.y >= area->y0 &&
                                  c.key.y <= area->y1);
    return inside && z >= band.z_min && z <= band.z_max;
  };
  std::int32_t x0 = std::numeric_limits<std::int32_t>::max(), y0 = x0;
  std::int32_t x1 = std::numeric_limits<std::int32_t>::min(), y1 = x1;
  for (const map_formats::CellRecord& c : cells.cells) {
    if (!inBand(c)) continue;
    x0 = std::min(x0, c.key.x);
    x1 = std::max(x1, c.key.x);
    y0 = std::min(y0, c.key.y);
    y1 = std::max(y1, c.key.y);
  }
  if (area && x0 <= x1) std::tie(x0, y0, x1, y1) = std::tie(area->x0, area->y0, area->x1, area->y1);
  if (x0 > x1)
    return Error{
        fmt::format("--png: no allocated cell has its centre in z [{}, {}] m", band.z_min, band.z_max)};
  const std::int64_t w = std::int64_t{x1} - x0 + 1, h = std::int64_t{y1} - y0 + 1;
  if (w > kMaxSide || h > kMaxSide)
    return Error{fmt::format("--png: the map is {} x {} cells, more than {} on a side", w, h, kMaxSide)};
  const auto n = static_cast<std::size_t>(w * h);
  std::vector<std::int8_t> cls(
      n, -2);  // -2 not observed, else the strongest class seen (occupied > free > unknown)
  std::vector<double> entropy_sum(n, 0.0);
  std::vector<int> count(n, 0);
  const auto rank = [](std::int8_t c) { return c == 1 ? 3 : c == -1 ? 2 : c == 0 ? 1 : 0; };
  for (const map_formats::CellRecord& c : cells.cells) {
    if (!inBand(c)) continue;
    // Row 0 is the top of the image: the largest y.
    const auto i = static_cast<std::size_t>(std::int64_t{y1 - c.key.y} * w + (c.key.x - x0));
    if (rank(c.cell_class) > rank(cls[i])) cls[i] = c.cell_class;
    entropy_sum[i] += filter::binaryEntropyBits(c.probability);
    ++count[i];
  }
  tools::MapRaster occupancy{static_cast<int>(w), static_cast<int>(h),   std::vector<tools::Rgb>(n),
                             cells.resolution,    x0 * cells.resolution, y0 * cells.resolution};
  tools::MapRaster entropy = occupancy;
  for (std::size_t i = 0; i < n; ++i) {
    occupancy.cells[i] = cls[i] > 0     ? kOccupied
                         : cls[i] == -1 ? kFree
                         : cls[i] == 0  ? kUnknown
                                        : kNotObserved;
    entropy.cells[i] = count[i] > 0 ? tools::sequentialColour(entropy_sum[i] / count[i]) : kNotObserved;
  }
  const std::string note = fmt::format("top-down, cells with centres in z {:.2f} to {:.2f} m; {} m cells",
                                       band.z_min, band.z_max, cells.resolution);
  tools::FigureKey classes;
  classes.legend = {
      {kOccupied, "occupied"}, {kFree, "free"}, {kUnknown, "unknown"}, {kNotObserved, "not observed"}};
  tools::FigureKey bits;
  bits.legend = {{kNotObserved, "not observed"}};
  bits.colour_bar =
      tools::ColourBar{tools::sequentialColour, "0 bit (certain)", "1 bit (prior)", "mean entropy"};
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{fmt::format("--png: {}: {}", dir.string(), ec.message())};
  std::string error;
  if (!tools::writePng(
          dir / "occupancy.png",
          tools::composeMapFigure(occupancy, "Occupancy: the class of each column", note, classes), error))
    return Error{"--png: " + error};
  if (!tools::writePng(dir / "entropy.png",
                       tools::composeMapFigure(entropy, "Entropy: what the map is unsure of", note, bits),
                       error))
    return Error{"--png: " + error};
  return TopDownSize{static_cast<int>(w), static_cast<int>(h)};
}

}  // namespace ogf::map_io
