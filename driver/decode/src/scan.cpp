#include "ogf/velodyne/scan.hpp"

namespace ogf::velodyne {

void Scan::clear() {
  std::vector<ScanPoint> keep = std::move(points);
  keep.clear();
  *this = Scan{};
  points = std::move(keep);
}

}  // namespace ogf::velodyne
