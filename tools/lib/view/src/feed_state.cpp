// The frames ogf-view's browsers get: see feed_state.hpp.
#include "ogf/view/feed_state.hpp"

#include <memory>
#include <string>
#include <utility>

#include "ogf/view/cell_frame.hpp"

namespace ogf::view {
namespace {

Frame textFrame(std::string s) { return Frame{std::make_shared<const std::string>(std::move(s)), false}; }

}  // namespace

std::vector<Frame> FeedState::cellFrames(std::span<const std::uint32_t> which, bool full) const {
  std::vector<Frame> out;
  for (auto& bytes : encodeCellFrames(slots_, which, full, stream_.resolution * slots_.lod()))
    out.push_back(Frame{std::make_shared<const std::string>(bytes.begin(), bytes.end()), true});
  return out;
}

void FeedState::refreshStream() {
  stream_.occupied = slots_.occupiedCells();
  stream_.boxes = slots_.occupied();
  stream_.lod = slots_.lod();
  if (!live_) return;
  stream_.seq = receiver_.appliedSeq();
  stream_.cells = receiver_.map().size();
  stream_.gaps = receiver_.gaps();
  stream_.keyframes = receiver_.keyframesApplied();
  stream_.malformed = receiver_.malformed() + decode_errors_;
  stream_.consistent = receiver_.consistent();
  stream_.waiting_for_keyframe = receiver_.needsKeyframe();
  stream_.resolution = receiver_.resolution();
}

std::vector<Frame> FeedState::wholeState() {
  if (whole_cells_.empty()) whole_cells_ = cellFrames(slots_.filledSlots(), true);
  if (!whole_figures_) {
    refreshStream();
    whole_figures_ = textFrame(figures_.json(stream_, 0, 0));
  }
  std::vector<Frame> out = whole_cells_;
  out.push_back(*whole_figures_);
  return out;
}

std::vector<Frame> FeedState::takeUpdate() {
  refreshStream();
  const bool full = slots_.takeFullPending();
  const auto changed = slots_.takeChanged();
  std::vector<Frame> update;
  if (full) {
    whole_cells_ = cellFrames(slots_.filledSlots(), true);
    update = whole_cells_;
  } else if (!changed.empty()) {
    whole_cells_.clear();
    update = cellFrames(changed, false);
  }
  whole_figures_.reset();
  update.push_back(textFrame(figures_.json(stream_, raw_sent_, corrected_sent_)));
  raw_sent_ = figures_.trail(false).points().size();
  corrected_sent_ = figures_.trail(true).points().size();
  return update;
}

}  // namespace ogf::view
