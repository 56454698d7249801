// ogf-mapper's snapshots (map_persistence.hpp): when one is due, the cut on the worker (the map encoded,
// the snapshot begun in the state directory), the file written on a thread of its own, and the snapshot
// put in place between two scans once written.
#include <ogf/filter/map_file.hpp>
#include <spdlog/spdlog.h>

#include <memory>
#include <system_error>

#include "ogf/mapper_daemon/daemon_time.hpp"
#include "ogf/mapper_daemon/map_persistence.hpp"

namespace ogf::mapper_daemon {

using Clock = std::chrono::steady_clock;

bool MapPersistence::snapshotDue(std::int64_t now) const {
  const auto snapshot_us = static_cast<std::int64_t>(options_.snapshot_interval_s * 1e6);
  return persisting() && now - last_snapshot_steady_ > snapshot_us;
}

bool MapPersistence::reopen() {
  // Persistence failed earlier (no space, read-only, I/O error): try the directory again, starting over
  // with a full snapshot of the map in memory.
  auto dir = persistence::StateDirectory::open(options_.state_dir);
  if (!dir) {
    failed(dir.error().message, true);
    return false;
  }
  auto rec = dir->recover(deltas_.mapId());
  if (!rec) {
    failed(rec.error().message, true);
    return false;
  }
  state_.emplace(std::move(*dir));
  snapshot_seq_ = -1;
  if (!pager_) openPager(state_->pagesDir());
  return true;
}

void MapPersistence::takeSnapshot(bool wait) {
  finishSnapshotWrite(wait);
  if (snapshot_write_) return;  // still being written: the next check between scans puts it in place
  last_snapshot_steady_ = steadyUtime();
  if (!state_ && retry_persistence_ && !reopen()) return;
  if (!state_ || snapshot_seq_ == deltas_.seq()) return;
  // The map in memory, and the pages holding the rest (a page is written before its region leaves memory;
  // the writer's thread flushes the new ones before the snapshot that names them).
  SnapshotWrite w;
  w.began = Clock::now();
  w.seq = deltas_.seq();
  auto bytes = filter::encodeMap(mapper_.filter());
  w.bytes = bytes.size();
  w.encode_ms = msSince(w.began);
  if (pager_) {
    w.pages = pager_->files();
    w.page_flush = pager_->takeUnsynced();
  }
  if (auto st = state_->beginSnapshot(w.seq); !st) {
    if (pager_) pager_->giveBackUnsynced(w.page_flush);
    state_.reset();
    failed(st.error().message, true);
    return;
  }
  startWriting(w, std::move(bytes));
  w.cut_ms = msSince(w.began);
  snapshot_write_ = std::move(w);
  if (wait) finishSnapshotWrite(true);
}

void MapPersistence::startWriting(SnapshotWrite& w, std::vector<std::uint8_t> bytes) {
  auto write = std::make_shared<std::function<SnapshotWritten()>>(
      [path = state_->snapshotPath(), id = state_->mapId(), seq = w.seq, bytes = std::move(bytes),
       pages = w.pages, flush = w.page_flush, retired = state_->retiredJournalPath()] {
        SnapshotWritten done;
        const auto began = Clock::now();
        done.status = persistence::MapPager::flushPages(flush);
        done.flush_ms = msSince(began);
        const auto flushed = Clock::now();
        if (!done.status) return done;
        done.status = persistence::StateDirectory::writeSnapshotFile(path, id, seq, bytes, pages);
        if (done.status) persistence::StateDirectory::retireOldJournal(retired);
        done.write_ms = msSince(flushed);
        return done;
      });
  try {
    w.written = std::async(std::launch::async, [write] { return (*write)(); });
  } catch (const std::system_error& e) {
    // No thread to be had (resource limits): the snapshot is written here, holding up mapping meanwhile.
    spdlog::warn("snapshot: no thread to write it on ({}); written on the worker", e.what());
    std::promise<SnapshotWritten> now;
    now.set_value((*write)());
    w.written = now.get_future();
  }
}

bool MapPersistence::snapshotWritten() const {
  return snapshot_write_ && snapshot_write_->written.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

void MapPersistence::finishSnapshotWrite(bool wait) {
  if (!snapshot_write_ || (!wait && !snapshotWritten())) return;
  SnapshotWrite w = std::move(*snapshot_write_);
  snapshot_write_.reset();
  const SnapshotWritten written = w.written.get();
  Status st = written.status;
  if (!st && pager_) pager_->giveBackUnsynced(w.page_flush);  // flushed by the next snapshot
  // Persistence failed while the file was written (a journal write): the directory is opened anew later.
  if (!state_) return;
  if (st) st = state_->finishSnapshot(w.pages);
  if (!st) {
    state_->abandonSnapshot();
    state_.reset();
    failed(st.error().message, true);
    return;
  }
  if (pager_) {
    // The pages a keyframe going out still reads stay too.
    auto keep = state_->referencedPages();
    const auto pinned = pinned_pages_ ? pinned_pages_() : std::vector<std::string>{};
    keep.insert(keep.end(), pinned.begin(), pinned.end());
    pager_->collect(keep);
  }
  snapshot_seq_ = w.seq;
  logSnapshotWritten(w, written);
  std::lock_guard lk(shared_.mu);
  if (!shared_.stats.persistence_ok)
    spdlog::info("persistence: {} is written again; the map is saved at seq {}", options_.state_dir.string(),
                 snapshot_seq_);
  shared_.stats.persistence_ok = true;
  shared_.stats.persistence_error.clear();
}

void MapPersistence::logSnapshotWritten(const SnapshotWrite& w, const SnapshotWritten& written) const {
  spdlog::info("snapshot at seq {}: {} bytes and {} pages in {:.0f} ms; the worker {:.0f} ms (encoding {:.0f}), "
               "its own thread flushing {} new pages {:.0f} ms and writing the file {:.0f} ms",
               snapshot_seq_, w.bytes, w.pages.size(), msSince(w.began), w.cut_ms, w.encode_ms,
               w.page_flush.names.size(), written.flush_ms, written.write_ms);
}

}  // namespace ogf::mapper_daemon
