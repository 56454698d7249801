#include "ogf/map_io/topdown_png.hpp"

#include <ogf/filter/occupancy.hpp>
#include <ogf/tools/png_writer.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace ogf::map_io {
namespace {

constexpr int kMaxSide = 16384;

std::uint8_t grey(double v01) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v01, 0.0, 1.0) * 255.0));
}

}  // namespace

Result<TopDownSize> writeTopDownPngs(const MapCells& cells, const TopDownBand& band, const std::filesystem::path& dir) {
  const auto inBand = [&](const CellRecord& c) {
    const double z = (c.key.z + 0.5) * cells.resolution;
    return z >= band.z_min && z <= band.z_max;
  };
  std::int32_t x0 = std::numeric_limits<std::int32_t>::max(), y0 = x0;
  std::int32_t x1 = std::numeric_limits<std::int32_t>::min(), y1 = x1;
  for (const CellRecord& c : cells.cells) {
    if (!inBand(c)) continue;
    x0 = std::min(x0, c.key.x);
    x1 = std::max(x1, c.key.x);
    y0 = std::min(y0, c.key.y);
    y1 = std::max(y1, c.key.y);
  }
  if (x0 > x1) return Error{fmt::format("--png: no allocated cell has its centre in z [{}, {}] m", band.z_min, band.z_max)};
  const std::int64_t w = std::int64_t{x1} - x0 + 1, h = std::int64_t{y1} - y0 + 1;
  if (w > kMaxSide || h > kMaxSide)
    return Error{fmt::format("--png: the map is {} x {} cells, more than {} on a side", w, h, kMaxSide)};
  const auto n = static_cast<std::size_t>(w * h);
  std::vector<double> max_p(n, -1.0), entropy_sum(n, 0.0);
  std::vector<int> count(n, 0);
  for (const CellRecord& c : cells.cells) {
    if (!inBand(c)) continue;
    // Row 0 is the top of the image: the largest y.
    const auto i = static_cast<std::size_t>(std::int64_t{y1 - c.key.y} * w + (c.key.x - x0));
    max_p[i] = std::max(max_p[i], c.probability);
    entropy_sum[i] += filter::binaryEntropyBits(c.probability);
    ++count[i];
  }
  tools::Image occupancy{static_cast<int>(w), static_cast<int>(h), 1, std::vector<std::uint8_t>(n)};
  tools::Image entropy = occupancy;
  for (std::size_t i = 0; i < n; ++i) {
    const double p = count[i] > 0 ? max_p[i] : 0.5;
    const double e = count[i] > 0 ? entropy_sum[i] / count[i] : 1.0;
    occupancy.pixels[i] = grey(1.0 - p);
    entropy.pixels[i] = grey(e);
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{fmt::format("--png: {}: {}", dir.string(), ec.message())};
  std::string error;
  if (!tools::writePng(dir / "occupancy.png", occupancy, error)) return Error{"--png: " + error};
  if (!tools::writePng(dir / "entropy.png", entropy, error)) return Error{"--png: " + error};
  return TopDownSize{static_cast<int>(w), static_cast<int>(h)};
}

}  // namespace ogf::map_io
