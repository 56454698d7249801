#include "ogf/map_formats/octomap_export.hpp"

#include <fmt/format.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>

namespace ogf::map_formats {

Result<OctomapExportCounts> writeOctomapBinary(const MapCells& cells, const std::filesystem::path& path) {
  octomap::OcTree tree(cells.resolution);
  OctomapExportCounts counts;
  for (const CellRecord& c : cells.cells) {
    if (c.cell_class == 0) continue;
    const Eigen::Vector3d centre = cellCentre(c.key, cells.resolution);
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(octomap::point3d(static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                                                 static_cast<float>(centre.z())),
                                key)) {
      ++counts.out_of_range;
      continue;
    }
    // Keep the class: an occupied cell must read occupied in OctoMap (threshold 0.5) even when rounding
    // brings p near it, so p is kept strictly on its side of 0.5.
    const double p = c.cell_class > 0 ? std::max(c.probability, 0.51) : std::min(c.probability, 0.49);
    tree.setNodeValue(key, octomap::logodds(p), /*lazy_eval=*/true);
    ++(c.cell_class > 0 ? counts.occupied : counts.free);
  }
  tree.updateInnerOccupancy();
  if (!tree.writeBinary(path.string())) return Error{fmt::format("{}: liboctomap could not write the tree", path.string())};
  return counts;
}

}  // namespace ogf::map_formats
