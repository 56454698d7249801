// The journal: every measurement set the mapper applied since its last snapshot, appended and flushed
// scan by scan, so that snapshot + journal replayed through the (deterministic) filter gives back exactly
// the map the mapper had at its last flush. A crash can tear only the record being written; the reader
// keeps every whole record before it and says where the tail was cut. Damage elsewhere (a flipped or
// overwritten stretch) loses only the records it touches: every record is framed by its magic and its
// checksum, so the reader resynchronises on the next record that is whole, and reports what it skipped.
//
// Format (little-endian):
//   header  "OGFJRNL1" | u32 version=2 | i64 map_id | i64 base_seq | u32 crc32(previous 28 bytes)
//   record  u32 0x3343524A ("JRC3") | u32 n | i64 seq | i64 utime | u32 length | the n measurements in
//           `length` bytes (measurement_coding.hpp, coding version 3, about 1.4 bytes a measurement for
//           a scan's set) | u32 crc32(record so far)
// Records u32 0x3243524A ("JRC2"), the same with coding version 2, are still read. Journals of version 1
// are still read too: their records are u32 0x4352524A ("JRRC") | u32 n | i64 seq | i64 utime |
// n x (i32 x, i32 y, i32 z, i8 y) | u32 crc32(record so far). Each record names its own form by its magic.
// base_seq is the update sequence of the snapshot this journal continues; records carry seq > base_seq,
// strictly increasing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ogf/common/result.hpp"
#include "ogf/core/measurement.hpp"

namespace ogf::persistence {

struct JournalRecord {
  std::int64_t seq = 0;
  std::int64_t utime = 0;
  std::vector<Measurement> measurements;
  std::uint64_t offset = 0;  // where the record starts in the file (set by readJournal)
};

// A stretch of the file skipped between two whole records (or between the header and the first).
struct JournalDamage {
  std::uint64_t offset = 0;
  std::uint64_t length = 0;
  std::string reason;
};

struct JournalContents {
  std::int64_t map_id = 0;    // 0 when the header is damaged
  std::int64_t base_seq = 0;  // 0 when the header is damaged
  // Why the header failed its checks ("" when it is whole); the records after it were still read.
  std::string header_damage;
  std::vector<JournalRecord> records;
  std::vector<JournalDamage> damaged;  // skipped stretches with whole records after them
  // Where an incomplete or corrupt tail began (a torn write at a crash), with the reason; nullopt when
  // the file ended on a record boundary.
  std::optional<std::uint64_t> torn_tail_offset;
  std::string torn_tail_reason;
};

// Reads a journal. Fails (with the path and offset) only when the file does not exist or holds neither a
// whole header nor a whole record; a damaged header, damaged records and a torn tail are reported in the
// contents, not as a failure.
Result<JournalContents> readJournal(const std::filesystem::path& path);

// Appends records to a journal file.
class JournalWriter {
 public:
  // Starts a new journal at `path` (replacing any file there) continuing snapshot `base_seq`.
  static Result<JournalWriter> create(const std::filesystem::path& path, std::int64_t map_id,
                                      std::int64_t base_seq);
  // Continues an existing journal after `contents` was read from it: a torn tail is cut off first, so
  // new records follow the last whole one.
  static Result<JournalWriter> resume(const std::filesystem::path& path, const JournalContents& contents);

  JournalWriter(JournalWriter&& o) noexcept;
  JournalWriter& operator=(JournalWriter&& o) noexcept;
  JournalWriter(const JournalWriter&) = delete;
  JournalWriter& operator=(const JournalWriter&) = delete;
  ~JournalWriter();

  // Buffers one record; nothing reaches the disk until flush(). seq must exceed the last one.
  Status append(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements);
  // Writes the buffered records and fdatasync()s: after this returns ok, they survive a crash.
  Status flush();

  std::int64_t lastSeq() const { return last_seq_; }
  std::uint64_t bytesWritten() const { return size_; }
  const std::filesystem::path& path() const { return path_; }
  // The open file was renamed to `path` (the writer keeps its descriptor): messages name it from now on.
  void renamedTo(std::filesystem::path path) { path_ = std::move(path); }

 private:
  JournalWriter(std::filesystem::path path, int fd, std::uint64_t size, std::int64_t last_seq)
      : path_(std::move(path)), fd_(fd), size_(size), last_seq_(last_seq) {}

  std::filesystem::path path_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::int64_t last_seq_ = 0;
  std::vector<std::byte> pending_;
};

}  // namespace ogf::persistence
