// The live navigation grid and its publishing rule (nav_feed.hpp).
#include "ogf/mapper_daemon/nav_feed.hpp"

#include <algorithm>
#include <iterator>

namespace ogf::mapper_daemon {

navigation::CellState cellStateOf(const delta::PublishedCell& cell) {
  return {cell.key, static_cast<double>(cell.probability) / delta::kProbabilityScale, cell.cell_class, cell.variance};
}

Result<NavFeed> NavFeed::create(double resolution, const navigation::NavBand& band, std::int64_t map_id,
                                const NavFeedTiming& timing) {
  auto projection = navigation::NavProjection::create(resolution, band);
  if (!projection) return projection.error();
  return NavFeed(std::move(*projection), map_id, timing);
}

void NavFeed::feed(std::span<const delta::PublishedCell> cells) {
  for (const auto& c : cells) projection_.update(cellStateOf(c));
}

void NavFeed::cellsChanged(std::span<const delta::PublishedCell> cells, std::int64_t scan_utime) {
  scan_utime_ = scan_utime;
  feed(cells);
  const auto changed = projection_.refresh();
  if (changed.empty()) return;
  std::vector<navigation::TileKey> merged;
  merged.reserve(waiting_.size() + changed.size());
  std::set_union(waiting_.begin(), waiting_.end(), changed.begin(), changed.end(), std::back_inserter(merged));
  waiting_ = std::move(merged);
}

void NavFeed::rebuild(std::span<const delta::PublishedCell> cells) {
  projection_.clear();
  addRestored(cells);
}

void NavFeed::addRestored(std::span<const delta::PublishedCell> cells) {
  feed(cells);
  projection_.refresh();
  waiting_.clear();
}

void NavFeed::newMap(std::int64_t map_id) {
  projection_.clear();
  waiting_.clear();
  stream_.reset(map_id, 0);
  keyframe_now_ = true;
}

NavFeed::Output NavFeed::turn(std::int64_t now) {
  if (!started_) {
    started_ = true;
    last_update_ = now - timing_.update_interval_us;  // the first changes go out at once
    last_keyframe_ = now;
  }
  Output out;
  if (!waiting_.empty() && now - last_update_ >= timing_.update_interval_us) {
    out.update = stream_.update(scan_utime_, projection_, waiting_);
    waiting_.clear();
    last_update_ = now;
  }
  const bool periodic = now - last_keyframe_ >= timing_.keyframe_interval_us;
  const bool asked = keyframe_requested_ && now - last_keyframe_ >= timing_.requested_keyframe_gap_us;
  if (keyframe_now_ || periodic || asked) {
    // After the update above, so a client that applied it finds the keyframe at its own seq (stale to it)
    // and one that missed something takes the keyframe and then the updates after it.
    out.keyframe = stream_.keyframe(scan_utime_, projection_);
    last_keyframe_ = now;
    keyframe_requested_ = false;
    keyframe_now_ = false;
  }
  return out;
}

}  // namespace ogf::mapper_daemon
