// Scan registration: each beam's cells by Bresenham's line from the sensor cell to the end cell.
#include "ogf/slam/map_update.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

#include "config_errors.hpp"

namespace ogf::slam {

Status MapUpdateConfig::validate() const {
  if (!(min_range_m >= 0.0) || !std::isfinite(min_range_m))
    return fieldError("min_range_m", "must be >= 0", min_range_m);
  if (!(usable_range_m > min_range_m) || !std::isfinite(usable_range_m)) {
    return fieldError("usable_range_m", "must be finite and > min_range_m", usable_range_m);
  }
  if (!(no_return_free_range_m >= 0.0) || no_return_free_range_m > usable_range_m) {
    return fieldError("no_return_free_range_m", "must be in [0, usable_range_m]", no_return_free_range_m);
  }
  return okStatus();
}

namespace {

// Visits every cell from `a` to `b` except `b` itself (Bresenham 1965).
template <class Visit>
void traceFree(CellIndex a, CellIndex b, Visit visit) {
  const int dx = std::abs(b.x - a.x), dy = -std::abs(b.y - a.y);
  const int sx = a.x < b.x ? 1 : -1, sy = a.y < b.y ? 1 : -1;
  int err = dx + dy;
  CellIndex c = a;
  while (!(c == b)) {
    visit(c);
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      c.x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      c.y += sy;
    }
  }
}

}  // namespace

void registerScan(TiledGrid& grid, const Pose2& robot_pose, const PlanarScan& scan,
                  const MapUpdateConfig& config) {
  const Pose2 sensor = compose(robot_pose, scan.sensor_pose);
  const CellIndex origin = grid.cellOf(sensor.x, sensor.y);
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    const float r = scan.ranges_m[i];
    if (!scan.isValid(r) || static_cast<double>(r) < config.min_range_m) continue;
    double range = r;
    bool hit = true;
    if (scan.isNoReturn(r)) {
      if (config.no_return_free_range_m <= 0.0) continue;
      range = config.no_return_free_range_m;
      hit = false;
    } else if (range > config.usable_range_m) {
      range = config.usable_range_m;
      hit = false;
    }
    const double a = sensor.theta + scan.bearing(i);
    const double ex = sensor.x + range * std::cos(a), ey = sensor.y + range * std::sin(a);
    const CellIndex end = grid.cellOf(ex, ey);
    traceFree(origin, end, [&](CellIndex c) { grid.recordVisit(c); });
    if (hit) {
      grid.recordHit(end, ex, ey);
    } else {
      grid.recordVisit(end);
    }
  }
}

}  // namespace ogf::slam
