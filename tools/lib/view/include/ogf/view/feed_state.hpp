// What ogf-view sends its browsers: the occupied cells (as binary cell frames, cell_frame.hpp), the tiles
// of the 2-D navigation grid (binary nav frames, nav_frame.hpp) and the figures (one JSON text frame,
// live_figures.hpp). A browser that joins gets the whole state; every tick the others get what changed
// since the last tick (cells, tiles) and the figures with the trails' points added since.
// The whole state is made once and shared by every browser that joins or catches up: the cells until they
// change, the figures until the next tick. No sockets: the program's server sends the frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/delta/map_receiver.hpp"
#include "ogf/navigation/nav_receiver.hpp"
#include "ogf/view/live_figures.hpp"
#include "ogf/view/nav_tiles.hpp"
#include "ogf/view/occupied_slots.hpp"
#include "ogf/view/view_server.hpp"

namespace ogf::view {

class FeedState {
 public:
  // `live`: the map follows the delta stream (the stream's figures come from the receiver); else it shows
  // a saved map, whose figures the program fills in once.
  explicit FeedState(bool live) : live_(live) {}

  OccupiedSlots& slots() { return slots_; }
  LiveFigures& figures() { return figures_; }
  StreamFigures& stream() { return stream_; }
  delta::MapReceiver& receiver() { return receiver_; }
  // A message on a subscribed channel that did not decode (shown with the stream's malformed count).
  void countDecodeError() { ++decode_errors_; }
  // The 2-D navigation grid: followed from OGF_NAV_GRID, or a saved map's grid given as a keyframe.
  navigation::NavReceiver& navReceiver() { return nav_receiver_; }
  // A message on the nav channel: `decoded` false when it did not decode (counted with the grid's
  // malformed messages).
  void countNavMessage(bool decoded) {
    ++nav_messages_;
    if (!decoded) ++nav_decode_errors_;
  }
  const NavFigures& nav() const { return nav_; }

  // Everything, for a browser that joins: every occupied box, every tile of the navigation grid, then the
  // figures with the whole trails.
  std::vector<Frame> wholeState();
  // One tick: the cells that changed (all of them after a reset), the navigation tiles that changed,
  // then the figures with the trails' points not sent before.
  std::vector<Frame> takeUpdate();

 private:
  void refreshStream();
  // Live, or a saved map's grid given: the figures carry "nav".
  bool showsNav() const { return live_ || nav_receiver_.keyframesApplied() > 0; }
  // The grid's figures; the tiles that changed since the last call when the receiver applied anything.
  std::vector<NavTile> refreshNav();
  std::vector<Frame> cellFrames(std::span<const std::uint32_t> which, bool full) const;
  std::vector<Frame> navFrames(std::span<const NavTile> tiles, bool full) const;

  bool live_;
  OccupiedSlots slots_;
  LiveFigures figures_;
  StreamFigures stream_;
  delta::MapReceiver receiver_;
  std::uint64_t decode_errors_ = 0;
  std::vector<Frame> whole_cells_;
  std::optional<Frame> whole_figures_;
  navigation::NavReceiver nav_receiver_;
  NavTiles nav_tiles_;
  NavFigures nav_;
  std::uint64_t nav_messages_ = 0;
  std::uint64_t nav_decode_errors_ = 0;
  // The receiver's (map id, applied seq, keyframes applied) the tiles were last brought to.
  std::optional<std::int64_t> nav_synced_map_;
  std::int64_t nav_synced_seq_ = -1;
  std::uint64_t nav_synced_keyframes_ = 0;
  std::vector<Frame> whole_nav_;
  std::size_t raw_sent_ = 0;        // trail points sent in the ticks so far
  std::size_t corrected_sent_ = 0;
};

}  // namespace ogf::view
