// Test helper: the mapper's side of OGF_NAV_GRID for a room, without a mapper: a NavProjection filled with
// the band's cells of a 3 m × 3 m room at 0.2 m (walls occupied, the floor inside free) and the NavStream
// that publishes it, as ogf-mapper does.
#pragma once

#include <lcm/lcm-cpp.hpp>

#include <cstddef>
#include <string>

#include "ogf/navigation/nav_projection.hpp"
#include "ogf/navigation/nav_stream.hpp"

namespace ogf::testing {

class NavRoom {
 public:
  static constexpr int kSide = 15;  // columns along each wall, the walls included

  explicit NavRoom(std::int64_t map_id = 40);

  // Known columns: the whole room.
  std::size_t knownColumns() const { return projection_.knownColumns(); }
  // Occupies the band over the columns [x0, x1) × [y0, y1) (a table in the room); returns the update.
  std::vector<ogf::nav_grid_t> addObstacle(int x0, int x1, int y0, int y1, std::int64_t utime);
  std::vector<ogf::nav_grid_t> keyframe(std::int64_t utime) const { return stream_.keyframe(utime, projection_); }
  const navigation::NavProjection& projection() const { return projection_; }

 private:
  navigation::NavProjection projection_;
  navigation::NavStream stream_;
};

void publishAll(lcm::LCM& lcm, const std::string& channel, const std::vector<ogf::nav_grid_t>& msgs);

}  // namespace ogf::testing
