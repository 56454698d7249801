#include "nav_room.hpp"

#include <utility>

namespace ogf::testing {
namespace {

constexpr double kResolution = 0.2;
// The default band (0.25..1.5 m above z = 0) holds layers 1..7 at 0.2 m; every one is observed.
constexpr int kLowLayer = 1;
constexpr int kHighLayer = 7;

navigation::CellState bandCell(int x, int y, int z, bool occupied) {
  return {{x, y, z}, occupied ? 0.9 : 0.1, occupied ? navigation::kClassOccupied : navigation::kClassFree, 0.01f};
}

}  // namespace

NavRoom::NavRoom(std::int64_t map_id)
    : projection_(std::move(navigation::NavProjection::create(kResolution, navigation::NavBand{}).value())),
      stream_(map_id) {
  for (int x = 0; x < kSide; ++x)
    for (int y = 0; y < kSide; ++y) {
      const bool wall = x == 0 || y == 0 || x == kSide - 1 || y == kSide - 1;
      for (int z = kLowLayer; z <= kHighLayer; ++z) projection_.update(bandCell(x, y, z, wall));
    }
  projection_.refresh();
}

std::vector<ogf::nav_grid_t> NavRoom::addObstacle(int x0, int x1, int y0, int y1, std::int64_t utime) {
  for (int x = x0; x < x1; ++x)
    for (int y = y0; y < y1; ++y) projection_.update(bandCell(x, y, kLowLayer + 2, true));
  const auto tiles = projection_.refresh();
  return stream_.update(utime, projection_, tiles);
}

void publishAll(lcm::LCM& lcm, const std::string& channel, const std::vector<ogf::nav_grid_t>& msgs) {
  for (const auto& m : msgs) lcm.publish(channel, &m);
}

}  // namespace ogf::testing
