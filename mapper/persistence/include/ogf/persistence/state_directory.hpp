// The mapper's state directory: the latest snapshot of the map and the journal of what was applied since,
// and the generation before them. Recovery = the snapshot's map plus the journal's records after it,
// replayed in order; because every scan's measurements are journalled and flushed before the map changes
// (write-ahead), a crash at any instant loses nothing that was flushed.
//
//   <dir>/snapshot.ogfs        "OGFSNAP1" | u32 version=1 | i64 map_id | i64 seq | u64 n | n bytes (the
//                              filter's map file) | u32 crc32(everything before), written atomically;
//                              version 2 (a map partly paged out) adds before the crc: u32 count |
//                              count × (u16 length | the name of a page file in <dir>/pages)
//   <dir>/pages/               the regions paged out (map_pager.hpp): the snapshot's map file holds the
//                              blocks in memory, the pages it names the rest
//   <dir>/journal.ogfj         see journal.hpp; its base_seq is the seq of the snapshot it continues
//   <dir>/snapshot.prev.ogfs   the snapshot before, and the journal that continued it up to the newest
//   <dir>/journal.prev.ogfj    snapshot (hard links, or copies where the file system has none)
//   <dir>/damaged-<utime>/     damaged files set aside, never deleted
//
//   <dir>/journal.next.ogfj    while a snapshot is being written: the journal that will continue it
//   <dir>/journal.retired.ogfj the journal of the generation before the previous one, deleted once the
//                              snapshot is written (a long journal takes a while to free)
//
// Snapshot then journal: the current pair becomes the previous generation, a new snapshot at seq s is
// renamed into place, then a fresh journal with base_seq s replaces the old one. A crash between the two
// leaves an old journal whose records up to s are already in the snapshot; recovery skips them.
//
// Writing a large snapshot takes a while, so it is split in three (snapshot() does all three in a row):
// beginSnapshot(s) turns the current pair into the previous generation and opens journal.next.ogfj with
// base_seq s; from then on journal() appends every record to both journals. writeSnapshotFile() writes
// snapshot.ogfs, on any thread, touching no other file. finishSnapshot() renames journal.next.ogfj into
// place. Until that rename, journal.ogfj holds every record since the old snapshot, so a crash at any
// instant leaves a pair that recovery reads as it is: the old snapshot with the whole journal, or the new
// snapshot with a journal whose records up to s it skips. Recovery never reads journal.next.ogfj; a
// crash leaves it behind, and the next beginSnapshot() replaces it.
//
// Damage: a damaged newest snapshot falls back to the previous one, replayed through both journals; a
// journal with damaged records gives every whole record (journal.hpp). Either way the damaged file is kept
// in damaged-<utime>/ and `damage` says what happened, so the daemon can report it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/persistence/journal.hpp"

namespace ogf::persistence {

struct RecoveredState {
  std::int64_t map_id = 0;         // 0 when the directory held nothing (a new map)
  std::int64_t snapshot_seq = 0;   // seq of the snapshot (0 without one)
  std::vector<std::uint8_t> snapshot_map;  // the filter's map file bytes; empty without a snapshot
  std::vector<std::string> pages;          // the page files in pages/ holding the rest of that map
  std::vector<JournalRecord> replay;       // records after the snapshot, in order
  std::int64_t last_seq = 0;       // snapshot_seq or the last record's seq
  std::vector<std::string> notes;  // what recovery skipped or cut, for the log
  // What was damaged and lost or fallen back from ("" when nothing): for persistence_ok = false. The
  // damaged files are listed in damaged_files; recover() sets them aside.
  std::string damage;
  std::vector<std::filesystem::path> damaged_files;
  bool snapshot_fallback = false;  // restored from the previous snapshot generation
};

class StateDirectory {
 public:
  // Uses `dir`, creating it when missing. Fails when it cannot be created or written, with the system's
  // reason (a read-only file system, no space, permission).
  static Result<StateDirectory> open(const std::filesystem::path& dir);

  // What recover() would restore from `dir`, read without writing anything: for a directory that cannot be
  // written (read-only), so the saved map is still used, and not replaced by a new one once it can be.
  static Result<RecoveredState> read(const std::filesystem::path& dir, std::int64_t new_map_id);

  // Reads the snapshot and the journal. A damaged snapshot falls back to the previous generation; when
  // both are damaged it is an error (never half-load a map). A torn journal tail is cut (noted); damaged
  // files are copied to damaged-<wall_utime>/ first. Then opens the journal for appending after the last
  // record.
  Result<RecoveredState> recover(std::int64_t new_map_id, std::int64_t wall_utime = 0);

  // Moves every state file into damaged-<wall_utime>/ (a map that cannot be restored: kept, never
  // deleted); returns that directory.
  Result<std::filesystem::path> setAside(std::int64_t wall_utime) const;

  // Appends one applied measurement set (write-ahead: call before the filter sees it) and flushes.
  Status journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements);

  // Writes a snapshot of the map at `seq` atomically and starts an empty journal after it. `pages` names the
  // files in pagesDir() that hold the blocks of the map not in `map_bytes`; they must be on disk already.
  Status snapshot(std::int64_t seq, std::span<const std::uint8_t> map_bytes, std::span<const std::string> pages = {});

  // The same in three steps (see the top of this file), for writing the file on another thread while the
  // map goes on: beginSnapshot at the cut (the map is at `seq`), writeSnapshotFile with the map at the cut
  // (snapshotPath() and mapId() of this directory), then finishSnapshot with the pages it names, or
  // abandonSnapshot when the write failed (the directory stays as it was: the old snapshot and the journal).
  Status beginSnapshot(std::int64_t seq);
  static Status writeSnapshotFile(const std::filesystem::path& path, std::int64_t map_id, std::int64_t seq,
                                  std::span<const std::uint8_t> map_bytes, std::span<const std::string> pages);
  Status finishSnapshot(std::span<const std::string> pages);
  // Deletes the journal beginSnapshot retired (retiredJournalPath()); any thread.
  static void retireOldJournal(const std::filesystem::path& path);
  void abandonSnapshot();
  bool snapshotBegun() const { return next_writer_.has_value(); }
  // The page files a restore may still need: those the newest snapshot and the one before it name (after
  // recover() and before the next snapshot, the restored snapshot's; the generation before it is replaced
  // by the next snapshot, so its pages are needed no more).
  std::vector<std::string> referencedPages() const;

  std::int64_t mapId() const { return map_id_; }
  std::uint64_t journalBytes() const { return writer_ ? writer_->bytesWritten() : 0; }
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path snapshotPath() const { return dir_ / "snapshot.ogfs"; }
  std::filesystem::path journalPath() const { return dir_ / "journal.ogfj"; }
  std::filesystem::path previousSnapshotPath() const { return dir_ / "snapshot.prev.ogfs"; }
  std::filesystem::path previousJournalPath() const { return dir_ / "journal.prev.ogfj"; }
  std::filesystem::path nextJournalPath() const { return dir_ / "journal.next.ogfj"; }
  std::filesystem::path retiredJournalPath() const { return dir_ / "journal.retired.ogfj"; }
  std::filesystem::path pagesDir() const { return dir_ / "pages"; }

 private:
  explicit StateDirectory(std::filesystem::path dir) : dir_(std::move(dir)) {}
  // The reading half of recover(); `resumable` is set when the journal continues the snapshot as it is.
  Result<RecoveredState> readState(std::int64_t new_map_id, std::optional<JournalContents>& resumable) const;

  std::filesystem::path dir_;
  std::int64_t map_id_ = 0;
  std::optional<JournalWriter> writer_;
  std::optional<JournalWriter> next_writer_;  // journal.next.ogfj between beginSnapshot and finishSnapshot
  std::vector<std::string> current_pages_;
  std::vector<std::string> previous_pages_;
};

// Encodes and decodes the snapshot container (exposed for tests and tools).
std::vector<std::byte> encodeSnapshot(std::int64_t map_id, std::int64_t seq, std::span<const std::uint8_t> map_bytes,
                                      std::span<const std::string> pages = {});
struct Snapshot {
  std::int64_t map_id = 0;
  std::int64_t seq = 0;
  std::vector<std::uint8_t> map_bytes;
  std::vector<std::string> pages;
};
Result<Snapshot> decodeSnapshot(std::span<const std::byte> bytes, const std::string& source);

}  // namespace ogf::persistence
