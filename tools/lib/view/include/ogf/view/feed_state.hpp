// What ogf-view sends its browsers: the occupied cells (as binary cell frames, cell_frame.hpp) and the
// figures (one JSON text frame, live_figures.hpp). A browser that joins gets the whole state; every tick
// the others get what changed since the last tick and the figures with the trails' points added since.
// The whole state is made once and shared by every browser that joins or catches up: the cells until they
// change, the figures until the next tick. No sockets: the program's server sends the frames.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ogf/delta/map_receiver.hpp"
#include "ogf/view/live_figures.hpp"
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

  // Everything, for a browser that joins: every occupied box, then the figures with the whole trails.
  std::vector<Frame> wholeState();
  // One tick: the cells that changed (all of them after a reset), then the figures with the trails'
  // points not sent before.
  std::vector<Frame> takeUpdate();

 private:
  void refreshStream();
  std::vector<Frame> cellFrames(std::span<const std::uint32_t> which, bool full) const;

  bool live_;
  OccupiedSlots slots_;
  LiveFigures figures_;
  StreamFigures stream_;
  delta::MapReceiver receiver_;
  std::uint64_t decode_errors_ = 0;
  std::vector<Frame> whole_cells_;
  std::optional<Frame> whole_figures_;
  std::size_t raw_sent_ = 0;        // trail points sent in the ticks so far
  std::size_t corrected_sent_ = 0;
};

}  // namespace ogf::view
