// The mapper's state directory: the latest snapshot of the map and the journal of what was applied since.
// Recovery = the snapshot's map plus the journal's records after it, replayed in order; because every
// scan's measurements are journalled and flushed before the map changes (write-ahead), a crash at any
// instant loses nothing that was flushed.
//
//   <dir>/snapshot.ogfs   "OGFSNAP1" | u32 version=1 | i64 map_id | i64 seq | u64 n | n bytes (the filter's
//                         map file) | u32 crc32(everything before), written atomically
//   <dir>/journal.ogfj    see journal.hpp; its base_seq is the seq of the snapshot it continues
//
// Snapshot then journal: a new snapshot at seq s is renamed into place first, then a fresh journal with
// base_seq s replaces the old one. A crash between the two leaves an old journal whose records up to s are
// already in the snapshot; recovery skips them.
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
  std::vector<JournalRecord> replay;       // records after the snapshot, in order
  std::int64_t last_seq = 0;       // snapshot_seq or the last record's seq
  std::vector<std::string> notes;  // what recovery skipped or cut, for the log
};

class StateDirectory {
 public:
  // Uses `dir`, creating it when missing. Fails when it cannot be created or written, with the system's
  // reason (a read-only file system, no space, permission).
  static Result<StateDirectory> open(const std::filesystem::path& dir);

  // What recover() would restore from `dir`, read without writing anything: for a directory that cannot be
  // written (read-only), so the saved map is still used, and not replaced by a new one once it can be.
  static Result<RecoveredState> read(const std::filesystem::path& dir, std::int64_t new_map_id);

  // Reads the snapshot and the journal. A damaged snapshot is an error (never half-load a map); a torn
  // journal tail is cut (noted). Then opens the journal for appending after the last record.
  Result<RecoveredState> recover(std::int64_t new_map_id);

  // Appends one applied measurement set (write-ahead: call before the filter sees it) and flushes.
  Status journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements);

  // Writes a snapshot of the map at `seq` atomically and starts an empty journal after it.
  Status snapshot(std::int64_t seq, std::span<const std::uint8_t> map_bytes);

  std::int64_t mapId() const { return map_id_; }
  std::uint64_t journalBytes() const { return writer_ ? writer_->bytesWritten() : 0; }
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path snapshotPath() const { return dir_ / "snapshot.ogfs"; }
  std::filesystem::path journalPath() const { return dir_ / "journal.ogfj"; }

 private:
  explicit StateDirectory(std::filesystem::path dir) : dir_(std::move(dir)) {}
  // The reading half of recover(); `resumable` is set when the journal continues the snapshot as it is.
  Result<RecoveredState> readState(std::int64_t new_map_id, std::optional<JournalContents>& resumable) const;

  std::filesystem::path dir_;
  std::int64_t map_id_ = 0;
  std::optional<JournalWriter> writer_;
};

// Encodes and decodes the snapshot container (exposed for tests and tools).
std::vector<std::byte> encodeSnapshot(std::int64_t map_id, std::int64_t seq, std::span<const std::uint8_t> map_bytes);
struct Snapshot {
  std::int64_t map_id = 0;
  std::int64_t seq = 0;
  std::vector<std::uint8_t> map_bytes;
};
Result<Snapshot> decodeSnapshot(std::span<const std::byte> bytes, const std::string& source);

}  // namespace ogf::persistence
