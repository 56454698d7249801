#include "ogf/map_formats/cell_csv.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>

namespace ogf::map_formats {

Status writeCellCsv(const MapCells& cells, const std::filesystem::path& path) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f) return Error{fmt::format("{}: cannot create CSV file", path.string())};
  fmt::memory_buffer buf;
  fmt::format_to(std::back_inserter(buf), "{}\n", kCellCsvHeader);
  for (const CellRecord& c : cells.cells) {
    const Eigen::Vector3d centre = cellCentre(c.key, cells.resolution);
    fmt::format_to(std::back_inserter(buf), "{:.4f},{:.4f},{:.4f},{:.6f},{},{:.6g}\n", centre.x(), centre.y(),
                   centre.z(), c.probability, static_cast<int>(c.cell_class), static_cast<double>(c.variance));
    if (buf.size() > (1U << 20)) {
      if (std::fwrite(buf.data(), 1, buf.size(), f.get()) != buf.size())
        return Error{fmt::format("{}: write failed", path.string())};
      buf.clear();
    }
  }
  if (std::fwrite(buf.data(), 1, buf.size(), f.get()) != buf.size() || std::fclose(f.release()) != 0)
    return Error{fmt::format("{}: write failed", path.string())};
  return okStatus();
}

}  // namespace ogf::map_formats
