// Occupied cells as binary PCD: see cell_pcd.hpp.
#include "ogf/map_formats/cell_pcd.hpp"

#include <fmt/format.h>

namespace ogf::map_formats {

Status writeOccupiedPcd(const MapCells& cells, const std::filesystem::path& path) {
  const std::size_t n = cells.occupiedCount();
  const std::string header = fmt::format(
      "# .PCD v0.7 - ogf-map: occupied OGF cells, centres in metres\n"
      "VERSION 0.7\nFIELDS x y z p variance\nSIZE 4 4 4 4 4\nTYPE F F F F F\nCOUNT 1 1 1 1 1\n"
      "WIDTH {}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {}\nDATA binary\n",
      n, n);
  return writeOccupiedPoints(cells, path, header, "PCD");
}

}  // namespace ogf::map_formats
