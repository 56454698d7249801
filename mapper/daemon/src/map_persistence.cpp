// ogf-mapper's map on disk (map_persistence.hpp): failures and damage as the log and the status say
// them, the journal, and the paging of far regions.
#include "ogf/mapper_daemon/map_persistence.hpp"

#include <spdlog/spdlog.h>

#include <system_error>

#include "ogf/mapper_daemon/daemon_time.hpp"

namespace ogf::mapper_daemon {

MapPersistence::MapPersistence(const MapperOptions& options, pipeline::ScanMapper& mapper, delta::DeltaStream& deltas,
                               SharedState& shared)
    : options_(options), mapper_(mapper), deltas_(deltas), shared_(shared) {}

void MapPersistence::failed(const std::string& what, bool retry) {
  std::lock_guard lk(shared_.mu);
  auto& stats = shared_.stats;
  // Said once per failure, not at every retry that meets the same one.
  if (stats.persistence_ok || stats.persistence_error != what)
    spdlog::error("persistence: {}; mapping goes on in memory{}", what,
                  retry ? ", the state directory is tried again at each snapshot" : "");
  stats.persistence_ok = false;
  stats.persistence_error = what;
  retry_persistence_ = retry;
}

void MapPersistence::reportDamage(const std::string& what) {
  std::lock_guard lk(shared_.mu);
  shared_.stats.persistence_ok = false;
  shared_.stats.persistence_error = what;
}

void MapPersistence::reportPageDamage(const std::vector<persistence::PageDamage>& damage) {
  for (const auto& d : damage) {
    const std::string what = d.reason + "; the cells of its region are lost";
    spdlog::error("paging: {}", what);
    reportDamage(what);
  }
}

void MapPersistence::journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements) {
  if (!state_) return;
  if (auto st = state_->journal(seq, utime, measurements); !st) {
    state_.reset();
    failed(st.error().message, true);
  }
}

void MapPersistence::openPager(const std::filesystem::path& pages_dir, bool holds_pages) {
  pager_.reset();
  paging_failed_ = false;
  if (!(options_.page_out_distance_m > 0) && !holds_pages) return;
  const double reach =
      persistence::MapPager::churnDistance(options_.map.fusion.measurement.max_range_m, options_.map.filter.resolution);
  if (options_.page_out_distance_m > 0 && options_.page_out_distance_m < reach)
    spdlog::warn("paging: page_out_distance_m {} m is within the scans' reach (max_range plus two regions, {:.1f} m): "
                 "regions will go out and come back scan after scan (the map is the same, the disk busier)",
                 options_.page_out_distance_m, reach);
  auto pager = persistence::MapPager::open(pages_dir);
  if (!pager) {
    spdlog::error("paging: {}; the whole map stays in memory", pager.error().message);
    return;
  }
  pager_.emplace(std::move(*pager));
}

void MapPersistence::holdPublished() {
  if (pager_) pager_->holdPublished(deltas_.map());
}

void MapPersistence::bringIn(std::span<const Measurement> measurements) {
  if (pager_) reportPageDamage(pager_->bringIn(mapper_.filter(), measurements, &deltas_.map()));
}

void MapPersistence::pageOut() {
  if (!pager_ || paging_failed_ || !(options_.page_out_distance_m > 0)) return;
  const Eigen::Vector3d at = mapper_.sensorOrigin();
  if (auto st = pager_->sendAway(mapper_.filter(), {at.x(), at.y(), at.z()}, options_.page_out_distance_m,
                                 &deltas_.map());
      !st) {
    // The regions not written stay in memory; those already out still come back when needed.
    paging_failed_ = true;
    spdlog::error("paging: {}; the map stays in memory from now on", st.error().message);
  }
}

filter::BlockHashSum MapPersistence::heldBlocks() const {
  return pager_ ? pager_->heldBlocks() : filter::BlockHashSum{};
}

void MapPersistence::beginNewMap(std::int64_t map_id) {
  if (state_) {
    // The old map is kept beside the new one, never deleted.
    const auto aside = options_.state_dir / ("reset-" + std::to_string(wallUtime()));
    std::error_code ec;
    std::filesystem::create_directories(aside, ec);
    const std::filesystem::path files[] = {state_->snapshotPath(), state_->journalPath(),
                                           state_->previousSnapshotPath(), state_->previousJournalPath(),
                                           state_->pagesDir()};
    pager_.reset();
    state_.reset();
    for (const auto& f : files) {
      if (std::filesystem::exists(f, ec)) std::filesystem::rename(f, aside / f.filename(), ec);
    }
    auto dir = persistence::StateDirectory::open(options_.state_dir);
    if (!dir) {
      failed(dir.error().message, true);
    } else if (auto rec = dir->recover(map_id); !rec) {
      failed(rec.error().message, true);
    } else {
      state_.emplace(std::move(*dir));
      openPager(state_->pagesDir());
    }
    spdlog::info("reset: the previous map is kept in {}", aside.string());
  }
  snapshot_seq_ = -1;
}

}  // namespace ogf::mapper_daemon
