// ogf-mapper's start from the state directory (map_persistence.hpp): the snapshot and the journal's scans
// since, the pages of the regions paged out; a directory that cannot be used is set aside or left alone,
// never half-loaded and never written over while the map it holds could still be rescued.
#include <spdlog/spdlog.h>

#include "map_id.hpp"
#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/map_persistence.hpp"

namespace ogf::mapper_daemon {

std::int64_t MapPersistence::restore() {
  if (options_.state_dir.empty()) return 0;
  auto dir = persistence::StateDirectory::open(options_.state_dir);
  if (!dir) {
    failed(dir.error().message, true);
    return restoreFromReadOnly();
  }
  return restoreFrom(std::move(*dir));
}

std::int64_t MapPersistence::restoreFromReadOnly() {
  // A directory that can be read but not written (read-only): still map on from the saved map, so that
  // once it is writable again the next snapshot holds the saved map and what was mapped since, instead
  // of replacing it with a map that lacks it.
  auto rec = persistence::StateDirectory::read(options_.state_dir, newMapId());
  if (!rec) {
    spdlog::error("state directory: {}; starting a new map in memory and not persisting", rec.error().message);
    retry_persistence_ = false;  // never write over a map that could not be read
    return 0;
  }
  if (applyRecovered(*rec, (options_.state_dir / "snapshot.ogfs").string())) return rec->last_seq;
  retry_persistence_ = false;
  return 0;
}

std::int64_t MapPersistence::restoreFrom(persistence::StateDirectory dir) {
  auto rec = dir.recover(newMapId(), wallUtime());
  const bool damaged = !rec && rec.error().is(ErrorKind::input_damaged);
  if (damaged) {
    // Never half-load a map, and never overwrite one that could still be rescued: set it aside.
    const auto aside = dir.setAside(wallUtime());
    spdlog::error("state directory: {}; moved to {} and starting a new map", rec.error().message,
                  aside ? aside->string() : aside.error().message);
    rec = dir.recover(newMapId(), wallUtime());
  }
  if (!rec && !damaged) {
    // Not known to be damaged (an I/O or resource error): the files stay as they are and nothing is
    // written over them; the next start reads them again.
    failed(rec.error().message + "; the state directory is left as it is and not written", false);
    return 0;
  }
  if (!rec) {
    failed(rec.error().message, true);
    return 0;
  }
  if (!applyRecovered(*rec, dir.snapshotPath().string())) {
    failed("the saved map cannot be restored (it does not fit the configuration, or its pages cannot be read; see "
           "the log); not persisting",
           false);
    return 0;
  }
  state_.emplace(std::move(dir));
  if (!pager_) openPager(state_->pagesDir());
  if (!rec->damage.empty()) {
    // Restored around damage: said until the next snapshot holds the map again.
    spdlog::error("state directory: {}", rec->damage);
    reportDamage(rec->damage);
  }
  return rec->last_seq;
}

bool MapPersistence::applyRecovered(const persistence::RecoveredState& rec, const std::string& snapshot_source) {
  for (const auto& note : rec.notes) spdlog::warn("state directory: {}", note);
  if (!rec.snapshot_map.empty()) {
    if (auto st = mapper_.restoreFilter(rec.snapshot_map, snapshot_source); !st) {
      spdlog::error("state directory: {}; starting a new map", st.error().message);
      return false;
    }
  }
  if (!rec.pages.empty()) {
    openPager(options_.state_dir / "pages", true);
    if (!pager_) {
      // Never write over a saved map whose pages could not even be listed.
      spdlog::error("state directory: the map's pages in {} cannot be read; starting a new map",
                    (options_.state_dir / "pages").string());
      if (auto fresh = pipeline::ScanMapper::create(options_.map)) mapper_ = std::move(*fresh);
      return false;
    }
    reportPageDamage(pager_->adopt(rec.pages, mapper_.filter()));
  }
  for (const auto& r : rec.replay) {
    if (pager_) reportPageDamage(pager_->bringIn(mapper_.filter(), r.measurements));
    mapper_.apply(r.measurements);
  }
  // The published map is built from the filter's cells in memory and the published cells the pages hold
  // (holdPublished()); pages of the first version hold none, so their regions come back for it.
  if (pager_) reportPageDamage(pager_->bringInUnpublished(mapper_.filter()));
  snapshot_seq_ = rec.snapshot_seq;
  // The whole map's cells and checksum, paged-out regions included, as the status reports them.
  const auto& map = mapper_.filter();
  const filter::BlockHashSum held = heldBlocks();
  // The map id the delta stream, queries and command replies carry: a restart is a new stream for clients
  // (they take a keyframe), so this run's id, not the one the state directory's files were written under.
  spdlog::info("restored map {} at seq {} (snapshot {} + {} journal records): {} cells, filter checksum {:016x}",
               deltas_.mapId(), rec.last_seq, rec.snapshot_seq, rec.replay.size(),
               map.allocatedCells() + held.blocks * map.cellsPerBlock(), map.checksum(held));
  return true;
}

}  // namespace ogf::mapper_daemon
