#include "ogf/map_formats/cell_ply.hpp"

#include <fmt/format.h>

namespace ogf::map_formats {

Status writeOccupiedPly(const MapCells& cells, const std::filesystem::path& path) {
  const std::string header = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment ogf-map: occupied OGF cells, centres in metres\n"
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n"
      "property float p\nproperty float variance\nend_header\n",
      cells.occupiedCount());
  return writeOccupiedPoints(cells, path, header, "PLY");
}

}  // namespace ogf::map_formats
