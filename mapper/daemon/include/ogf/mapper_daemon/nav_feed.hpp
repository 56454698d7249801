// The live 2-D navigation grid of ogf-mapper's map and the rule it goes out by on OGF_NAV_GRID: a
// NavProjection fed with the cells each scan changed (the mapper's published cells: quantised predictive
// probability, class, variance), the tiles whose columns changed gathered until the next update is due,
// and the NavStream that numbers the updates. What goes out when (turn()):
//  - an update (seq + 1) with the tiles changed since the last one, when some changed and update_interval
//    has passed since the last update;
//  - a keyframe (every known tile) every keyframe_interval, when asked for (at most one asked-for keyframe
//    per requested_keyframe_gap, so a flood of requests costs a bounded rate), and at once for a new map.
// Pure: no LCM, no clock; the daemon's NavPublisher passes the steady time and publishes what comes back.
#pragma once

#include <ogf/nav_grid_t.hpp>

#include <cstdint>
#include <span>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/delta/published_cell.hpp"
#include "ogf/navigation/nav_band.hpp"
#include "ogf/navigation/nav_projection.hpp"
#include "ogf/navigation/nav_stream.hpp"

namespace ogf::mapper_daemon {

struct NavFeedTiming {
  std::int64_t update_interval_us = 500'000;
  std::int64_t keyframe_interval_us = 5'000'000;
  std::int64_t requested_keyframe_gap_us = 1'000'000;
};

class NavFeed {
 public:
  // Error when the band holds no layer at `resolution` (NavBand::validate).
  static Result<NavFeed> create(double resolution, const navigation::NavBand& band, std::int64_t map_id,
                                const NavFeedTiming& timing);

  // The cells a scan changed (stamped `scan_utime`, the scan's time); their columns are reclassified now.
  void cellsChanged(std::span<const delta::PublishedCell> cells, std::int64_t scan_utime);
  // The grid of a whole map (a map restored at start): replaces what the projection held; nothing waits to
  // go out (clients of a new map id start from a keyframe).
  void rebuild(std::span<const delta::PublishedCell> cells);
  // Adds cells to the grid without making their tiles wait for an update (the rest of a restored map).
  void addRestored(std::span<const delta::PublishedCell> cells);
  // A new, empty map `map_id`: its grid is empty, numbered from 0, and its first keyframe goes out at the
  // next turn.
  void newMap(std::int64_t map_id);
  // A keyframe asked for (on the request channel).
  void requestKeyframe() { keyframe_requested_ = true; }

  struct Output {
    std::vector<ogf::nav_grid_t> update;    // empty when no update went out
    std::vector<ogf::nav_grid_t> keyframe;  // empty when no keyframe went out
  };
  // What goes out at steady time `now` (microseconds). The clocks start at the first turn.
  Output turn(std::int64_t now);

  const navigation::NavProjection& projection() const { return projection_; }
  std::int64_t seq() const { return stream_.seq(); }
  std::int64_t mapId() const { return stream_.mapId(); }
  // Tiles changed since the last update, waiting for it.
  std::size_t tilesWaiting() const { return waiting_.size(); }

 private:
  NavFeed(navigation::NavProjection projection, std::int64_t map_id, const NavFeedTiming& timing)
      : projection_(std::move(projection)), stream_(map_id), timing_(timing) {}
  void feed(std::span<const delta::PublishedCell> cells);

  navigation::NavProjection projection_;
  navigation::NavStream stream_;
  NavFeedTiming timing_;
  std::vector<navigation::TileKey> waiting_;  // sorted, unique
  std::int64_t scan_utime_ = 0;
  bool started_ = false;
  std::int64_t last_update_ = 0;
  std::int64_t last_keyframe_ = 0;
  bool keyframe_requested_ = false;
  bool keyframe_now_ = false;  // a new map's first keyframe
};

// A published cell as the projection reads it: probability p·10000 back to p.
navigation::CellState cellStateOf(const delta::PublishedCell& cell);

}  // namespace ogf::mapper_daemon
