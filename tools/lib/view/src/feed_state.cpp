// The frames ogf-view's browsers get: see feed_state.hpp.
#include "ogf/view/feed_state.hpp"

#include <memory>
#include <string>
#include <utility>

#include "ogf/view/cell_frame.hpp"
#include "ogf/view/nav_frame.hpp"

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

std::vector<Frame> FeedState::navFrames(std::span<const NavTile> tiles, bool full) const {
  std::vector<Frame> out;
  for (auto& bytes : encodeNavFrames(tiles, full, nav_.resolution, nav_.floor_z))
    out.push_back(Frame{std::make_shared<const std::string>(bytes.begin(), bytes.end()), true});
  return out;
}

std::vector<NavTile> FeedState::refreshNav() {
  const auto& r = nav_receiver_;
  std::vector<NavTile> changed;
  if (r.mapId() != nav_synced_map_ || r.appliedSeq() != nav_synced_seq_ ||
      r.keyframesApplied() != nav_synced_keyframes_) {
    changed = nav_tiles_.follow(r);
    nav_synced_map_ = r.mapId();
    nav_synced_seq_ = r.appliedSeq();
    nav_synced_keyframes_ = r.keyframesApplied();
  }
  nav_.seq = r.appliedSeq();
  nav_.known_columns = r.knownColumns();
  nav_.tiles = nav_tiles_.size();
  nav_.tiles_not_drawn = nav_tiles_.notDrawn();
  nav_.gaps = r.gaps();
  nav_.keyframes = r.keyframesApplied();
  nav_.malformed = r.malformed() + nav_decode_errors_;
  nav_.messages = nav_messages_;
  nav_.consistent = r.consistent();
  nav_.waiting_for_keyframe = r.needsKeyframe();
  nav_.resolution = r.resolution();
  nav_.floor_z = r.band().floor_z;
  nav_.min_height = r.band().min_height;
  nav_.max_height = r.band().max_height;
  return changed;
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
    whole_figures_ = textFrame(figures_.json(stream_, 0, 0, showsNav() ? &nav_ : nullptr));
  }
  if (whole_nav_.empty()) whole_nav_ = navFrames(nav_tiles_.all(), true);
  std::vector<Frame> out = whole_cells_;
  out.insert(out.end(), whole_nav_.begin(), whole_nav_.end());
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
  // Tiles the whole state does not have yet are sent to every browser; the whole state is made again.
  if (const auto tiles = refreshNav(); !tiles.empty()) {
    whole_nav_.clear();
    for (auto& f : navFrames(tiles, false)) update.push_back(std::move(f));
  }
  whole_figures_.reset();
  update.push_back(textFrame(figures_.json(stream_, raw_sent_, corrected_sent_, showsNav() ? &nav_ : nullptr)));
  raw_sent_ = figures_.trail(false).points().size();
  corrected_sent_ = figures_.trail(true).points().size();
  return update;
}

}  // namespace ogf::view
