#include "ogf/map_formats/map_cells.hpp"

#include <ogf/filter/occupancy.hpp>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <string>

namespace ogf::map_formats {

std::size_t MapCells::occupiedCount() const {
  return static_cast<std::size_t>(
      std::count_if(cells.begin(), cells.end(), [](const CellRecord& c) { return c.cell_class > 0; }));
}

MapCells collectCells(const filter::BandedOgf& map) {
  MapCells out;
  const auto& cfg = map.config();
  out.resolution = cfg.resolution;
  out.cells.reserve(map.allocatedCells());
  map.forEachCell([&](const CellKey& key, float mean, float variance) {
    out.cells.push_back({key, filter::predictiveProbability(mean, variance),
                         filter::occupancyClass(mean, cfg.occupiedThreshold, cfg.freeThreshold), variance});
  });
  return out;
}

static_assert(std::endian::native == std::endian::little, "point records are written in native (little) order");

std::vector<char> occupiedPointRecords(const MapCells& cells) {
  std::vector<char> body;
  body.reserve(cells.occupiedCount() * 5 * sizeof(float));
  for (const CellRecord& c : cells.cells) {
    if (c.cell_class <= 0) continue;
    const Eigen::Vector3d centre = cellCentre(c.key, cells.resolution);
    const float v[5] = {static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                        static_cast<float>(centre.z()), static_cast<float>(c.probability), c.variance};
    const std::size_t at = body.size();
    body.resize(at + sizeof v);
    std::memcpy(body.data() + at, v, sizeof v);
  }
  return body;
}

Status writeOccupiedPoints(const MapCells& cells, const std::filesystem::path& path, std::string_view header,
                           std::string_view kind) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Error{path.string() + ": cannot create " + std::string(kind) + " file"};
  out << header;
  const std::vector<char> body = occupiedPointRecords(cells);
  out.write(body.data(), static_cast<std::streamsize>(body.size()));
  out.close();
  if (!out) return Error{path.string() + ": write failed"};
  return okStatus();
}

}  // namespace ogf::map_formats
