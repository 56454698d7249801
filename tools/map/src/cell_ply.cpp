#include "ogf/map_io/cell_ply.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <fstream>
#include <vector>

namespace ogf::map_io {

static_assert(std::endian::native == std::endian::little, "the PLY body is written in native (little) order");

Status writeOccupiedPly(const MapCells& cells, const std::filesystem::path& path) {
  const std::size_t n = cells.occupiedCount();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Error{fmt::format("{}: cannot create PLY file", path.string())};
  out << "ply\nformat binary_little_endian 1.0\ncomment ogf-map: occupied OGF cells, centres in metres\n"
      << "element vertex " << n << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "property float p\nproperty float variance\nend_header\n";
  std::vector<char> body;
  body.reserve(n * 5 * sizeof(float));
  for (const CellRecord& c : cells.cells) {
    if (c.cell_class <= 0) continue;
    const Eigen::Vector3d centre = cellCentre(c.key, cells.resolution);
    const float v[5] = {static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                        static_cast<float>(centre.z()), static_cast<float>(c.probability), c.variance};
    const std::size_t at = body.size();
    body.resize(at + sizeof v);
    std::memcpy(body.data() + at, v, sizeof v);
  }
  out.write(body.data(), static_cast<std::streamsize>(body.size()));
  out.close();
  if (!out) return Error{fmt::format("{}: write failed", path.string())};
  return okStatus();
}

}  // namespace ogf::map_io
