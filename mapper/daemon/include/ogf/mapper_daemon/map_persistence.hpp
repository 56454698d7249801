// ogf-mapper's map on disk: the state directory (snapshot, journal) and the pager (regions paged out to
// the directory's pages/). It restores the map at the start (map_restore.cpp), journals each scan before
// the map changes, pages far regions out and back in (map_persistence.cpp), and schedules and writes snapshots
// (snapshot_schedule.cpp). A persistence failure is logged once, reported in the status, and mapping goes
// on in memory; after an I/O failure the directory is tried again at each snapshot.
#pragma once

#include <ogf/filter/banded_ogf.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <future>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/core/measurement.hpp"
#include "ogf/delta/delta_stream.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"
#include "ogf/mapper_daemon/shared_state.hpp"
#include "ogf/persistence/map_pager.hpp"
#include "ogf/persistence/state_directory.hpp"
#include "ogf/pipeline/scan_mapper.hpp"

namespace ogf::mapper_daemon {

class MapPersistence {
 public:
  // The file names of the pages a keyframe going out still reads (KeyframeSender::pinnedPages).
  using PinnedPages = std::function<std::vector<std::string>()>;

  // `mapper` and `deltas` are the map in memory and the published map, both the worker's.
  MapPersistence(const MapperOptions& options, pipeline::ScanMapper& mapper, delta::DeltaStream& deltas,
                 SharedState& shared);
  MapPersistence(const MapPersistence&) = delete;
  MapPersistence& operator=(const MapPersistence&) = delete;

  void setPinnedPages(PinnedPages pinned) { pinned_pages_ = std::move(pinned); }

  // Restores the map from the state directory when one is configured; returns the seq it resumes at (0
  // for a new map). Problems are logged and reported in the status, never fatal (map_restore.cpp).
  std::int64_t restore();
  // The published map, restored: the pages keep the published cells of the regions they hold.
  void holdPublished();

  // The scan path (the worker's). Write-ahead: the journal holds the scan before the map changes, so what
  // a client is told exists on disk.
  void journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements);
  // Brings in the paged-out regions the measurements reach.
  void bringIn(std::span<const Measurement> measurements);
  // Pages the far regions out after a scan; a failure is said once and leaves the map in memory.
  void pageOut();
  // The regions paged out, counted in the map's cells and checksum.
  filter::BlockHashSum heldBlocks() const;
  // The pager, or null when the whole map is in memory.
  persistence::MapPager* pager() { return pager_ ? &*pager_ : nullptr; }
  // Logs damaged pages (their regions are lost) and reports them in the status.
  void reportPageDamage(const std::vector<persistence::PageDamage>& damage);

  // Snapshots (every snapshot_interval_s, on the save command, at stop): the worker encodes the map and
  // begins the snapshot in the state directory; a thread flushes the new pages and writes the file while
  // the worker maps on, journalling each scan into the journals before and after the cut
  // (state_directory.hpp).
  // The snapshot clock starts with the worker.
  void startClock(std::int64_t now) { last_snapshot_steady_ = now; }
  // Whether the map is written to a state directory (or is to be again, after an I/O failure).
  bool persisting() const { return state_.has_value() || retry_persistence_; }
  bool snapshotDue(std::int64_t now) const;
  // `wait`: returns with the snapshot in place (the save command, stop). One at a time: a snapshot due while
  // one is written waits for it.
  void takeSnapshot(bool wait = false);
  // Puts the snapshot being written in place once its file is written (`wait`: waits for that); nothing
  // when none is being written.
  void finishSnapshotWrite(bool wait);
  bool snapshotWritten() const;
  // Whether a state directory is open (the save command needs one).
  bool hasStateDirectory() const { return state_.has_value(); }

  // A map reset (the worker's, the new map in place as map id `map_id`): the old map's files are kept
  // aside in the state directory, never deleted, and a new directory is begun; the next snapshot is full.
  void beginNewMap(std::int64_t map_id);

 private:
  // Logs (once per distinct failure) and reports it in the status; `retry`: try the directory again at
  // each snapshot (an I/O failure), not when writing would replace a saved map that could not be used.
  void failed(const std::string& what, bool retry);
  void reportDamage(const std::string& what);
  std::int64_t restoreFromReadOnly();
  std::int64_t restoreFrom(persistence::StateDirectory dir);
  bool applyRecovered(const persistence::RecoveredState& rec, const std::string& snapshot_source);
  // Paging (page_out_distance_m): the pager on the state directory's pages/, opened with the directory,
  // and also when paging is off but the saved map has pages (`holds_pages`). Damaged pages lose their
  // regions: logged and reported in the status like other damage.
  void openPager(const std::filesystem::path& pages_dir, bool holds_pages = false);
  // Opens the state directory again after a failure; false when it still fails.
  bool reopen();
  // What the writer's thread did: flushed the pages written since the last snapshot, then wrote the file.
  struct SnapshotWritten {
    Status status = okStatus();
    double flush_ms = 0;
    double write_ms = 0;
  };
  struct SnapshotWrite {
    std::int64_t seq = 0;
    std::vector<std::string> pages;  // the page files it names
    persistence::MapPager::PageFlush page_flush;
    std::size_t bytes = 0;
    double cut_ms = 0;     // on the worker, in all: encoding, beginning the snapshot
    double encode_ms = 0;  // on the worker: encoding the map in memory
    std::chrono::steady_clock::time_point began;
    std::future<SnapshotWritten> written;
  };
  // Starts the writer's thread (or writes on the worker when no thread can be had).
  void startWriting(SnapshotWrite& w, std::vector<std::uint8_t> bytes);
  void logSnapshotWritten(const SnapshotWrite& w, const SnapshotWritten& written) const;

  const MapperOptions& options_;
  pipeline::ScanMapper& mapper_;
  delta::DeltaStream& deltas_;
  SharedState& shared_;
  PinnedPages pinned_pages_;

  std::optional<persistence::StateDirectory> state_;
  std::optional<persistence::MapPager> pager_;
  bool paging_failed_ = false;
  std::int64_t last_snapshot_steady_ = 0;
  std::int64_t snapshot_seq_ = 0;
  std::optional<SnapshotWrite> snapshot_write_;
  bool retry_persistence_ = false;
};

}  // namespace ogf::mapper_daemon
