#include "ogf/persistence/state_directory.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "ogf/common/atomic_file.hpp"
#include "ogf/common/crc32.hpp"
#include "ogf/common/little_endian.hpp"
#include "ogf/common/read_file.hpp"

namespace ogf::persistence {
namespace {

constexpr char kSnapshotMagic[8] = {'O', 'G', 'F', 'S', 'N', 'A', 'P', '1'};
// Version 2 adds the pages that hold the rest of the map; a snapshot without pages is written as version 1.
constexpr std::uint32_t kSnapshotVersion = 1;
constexpr std::uint32_t kSnapshotVersionWithPages = 2;
constexpr std::size_t kFixed = 8 + 4 + 8 + 8 + 8;

}  // namespace

std::vector<std::byte> encodeSnapshot(std::int64_t map_id, std::int64_t seq, std::span<const std::uint8_t> map_bytes,
                                      std::span<const std::string> pages) {
  std::vector<std::byte> out;
  out.reserve(kFixed + map_bytes.size() + 4);
  for (char c : kSnapshotMagic) out.push_back(static_cast<std::byte>(c));
  putLittleEndian<std::uint32_t>(out, pages.empty() ? kSnapshotVersion : kSnapshotVersionWithPages);
  putLittleEndian<std::int64_t>(out, map_id);
  putLittleEndian<std::int64_t>(out, seq);
  putLittleEndian<std::uint64_t>(out, map_bytes.size());
  const auto* map = reinterpret_cast<const std::byte*>(map_bytes.data());
  out.insert(out.end(), map, map + map_bytes.size());
  if (!pages.empty()) {
    putLittleEndian<std::uint32_t>(out, static_cast<std::uint32_t>(pages.size()));
    for (const std::string& name : pages) {
      putLittleEndian<std::uint16_t>(out, static_cast<std::uint16_t>(name.size()));
      for (char c : name) out.push_back(static_cast<std::byte>(c));
    }
  }
  putLittleEndian<std::uint32_t>(out, crc32(out.data(), out.size()));
  return out;
}

Result<Snapshot> decodeSnapshot(std::span<const std::byte> bytes, const std::string& source) {
  const auto fail = [&](std::size_t offset, const std::string& what) {
    return Error::inputDamaged(source + ": offset " + std::to_string(offset) + ": " + what);
  };
  if (bytes.size() < kFixed + 4) return fail(0, "snapshot truncated (" + std::to_string(bytes.size()) + " bytes)");
  if (std::memcmp(bytes.data(), kSnapshotMagic, sizeof(kSnapshotMagic)) != 0)
    return fail(0, "not an ogf snapshot (bad magic)");
  const auto version = getLittleEndian<std::uint32_t>(bytes.data() + 8);
  if (version != kSnapshotVersion && version != kSnapshotVersionWithPages)
    return fail(8, "unsupported snapshot version " + std::to_string(version));
  const std::size_t crcAt = bytes.size() - 4;
  const auto n = getLittleEndian<std::uint64_t>(bytes.data() + 28);
  if (version == kSnapshotVersion ? n != crcAt - kFixed : n > crcAt - kFixed)
    return fail(28, "map length " + std::to_string(n) + " does not match the file (" + std::to_string(crcAt - kFixed) +
                        " bytes follow): truncated or corrupt");
  if (getLittleEndian<std::uint32_t>(bytes.data() + crcAt) != crc32(bytes.data(), crcAt))
    return fail(crcAt, "snapshot checksum mismatch");
  Snapshot s;
  s.map_id = getLittleEndian<std::int64_t>(bytes.data() + 12);
  s.seq = getLittleEndian<std::int64_t>(bytes.data() + 20);
  s.map_bytes.resize(n);
  std::memcpy(s.map_bytes.data(), bytes.data() + kFixed, n);
  if (version == kSnapshotVersionWithPages) {
    std::size_t at = kFixed + n;
    if (crcAt - at < 4) return fail(at, "page count: snapshot truncated");
    const auto count = getLittleEndian<std::uint32_t>(bytes.data() + at);
    at += 4;
    for (std::uint32_t i = 0; i < count; ++i) {
      if (crcAt - at < 2) return fail(at, "page name " + std::to_string(i) + ": snapshot truncated");
      const auto len = getLittleEndian<std::uint16_t>(bytes.data() + at);
      at += 2;
      if (crcAt - at < len) return fail(at, "page name " + std::to_string(i) + ": snapshot truncated");
      std::string name(reinterpret_cast<const char*>(bytes.data() + at), len);
      if (name.empty() || name.find('/') != std::string::npos || name.front() == '.')
        return fail(at, "page name '" + name + "' is not a file name");
      s.pages.push_back(std::move(name));
      at += len;
    }
    if (at != crcAt) return fail(at, std::to_string(crcAt - at) + " bytes after the page names");
  }
  return s;
}

Result<StateDirectory> StateDirectory::open(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error::system(dir.string() + ": cannot create the state directory", ec);
  if (::access(dir.c_str(), W_OK) != 0)
    return Error::system(dir.string() + ": the state directory is not writable");
  return StateDirectory(dir);
}

Result<RecoveredState> StateDirectory::read(const std::filesystem::path& dir, std::int64_t new_map_id) {
  std::optional<JournalContents> resumable;
  return StateDirectory(dir).readState(new_map_id, resumable);
}

Result<RecoveredState> StateDirectory::recover(std::int64_t new_map_id, std::int64_t wall_utime) {
  std::optional<JournalContents> resumable;
  auto state = readState(new_map_id, resumable);
  if (!state) return state.error();
  RecoveredState& out = *state;
  map_id_ = out.map_id;
  abandonSnapshot();
  // The pages the restored snapshot names; after the next snapshot they are the previous generation's.
  current_pages_ = out.pages;
  previous_pages_.clear();
  writer_.reset();
  std::error_code ec;
  if (!out.damaged_files.empty()) {
    // Kept before anything here is rewritten; copies, so that a failure to keep them changes nothing.
    const auto aside = dir_ / ("damaged-" + std::to_string(wall_utime));
    std::filesystem::create_directories(aside, ec);
    for (const auto& f : out.damaged_files) {
      if (!ec) std::filesystem::copy_file(f, aside / f.filename(), std::filesystem::copy_options::overwrite_existing, ec);
    }
    if (ec) return Error::system(aside.string() + ": cannot keep the damaged files", ec);
    out.damage += "; the damaged files are kept in " + aside.string();
    out.notes.push_back("the damaged files are kept in " + aside.string());
  }
  if (out.snapshot_fallback) {
    // The previous snapshot is the newest good one now; the damaged one is kept aside.
    std::filesystem::rename(previousSnapshotPath(), snapshotPath(), ec);
    if (ec) return Error::system(snapshotPath().string() + ": cannot restore the previous snapshot", ec);
  }
  if (resumable) {
    // The journal continues the snapshot: keep appending to it.
    auto w = JournalWriter::resume(journalPath(), *resumable);
    if (!w) return w.error();
    writer_.emplace(std::move(*w));
  } else {
    // No journal to continue: write the replayed records into a fresh one after the snapshot, so the
    // directory again holds snapshot + journal = the map. Written beside it and renamed, since the journal
    // may share its file with the previous generation's.
    const std::filesystem::path fresh = journalPath().string() + ".new";
    auto w = JournalWriter::create(fresh, map_id_, out.snapshot_seq);
    if (!w) return w.error();
    for (const auto& rec : out.replay)
      if (auto st = w->append(rec.seq, rec.utime, rec.measurements); !st) return st.error();
    if (auto st = w->flush(); !st) return st.error();
    std::filesystem::rename(fresh, journalPath(), ec);
    if (ec) return Error::system(journalPath().string() + ": cannot replace the journal", ec);
    w->renamedTo(journalPath());
    writer_.emplace(std::move(*w));
  }
  return state;
}

Result<std::filesystem::path> StateDirectory::setAside(std::int64_t wall_utime) const {
  const auto aside = dir_ / ("damaged-" + std::to_string(wall_utime));
  std::error_code ec;
  std::filesystem::create_directories(aside, ec);
  if (ec) return Error::system(aside.string(), ec);
  for (const auto& f : {snapshotPath(), journalPath(), previousSnapshotPath(), previousJournalPath()}) {
    if (!std::filesystem::exists(f, ec)) continue;
    std::filesystem::rename(f, aside / f.filename(), ec);
    if (ec) return Error::system(f.string() + ": cannot move it to " + aside.string(), ec);
  }
  if (std::filesystem::exists(pagesDir(), ec)) {
    // The pages belong to the snapshots set aside.
    std::filesystem::rename(pagesDir(), aside / "pages", ec);
    if (ec) return Error::system(pagesDir().string() + ": cannot move it to " + aside.string(), ec);
  }
  return aside;
}

namespace {

// The snapshot at `path`: nullopt when there is none; an error naming the file and offset when damaged
// (input_damaged), or the system's reason when it cannot be read (io, resource).
std::optional<Result<Snapshot>> loadSnapshot(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  const auto raw = readWholeFile(path);
  if (!raw) return raw.error();
  return decodeSnapshot(*raw, path.string());
}

// A file that could not be read is not known to be damaged: recovery stops with the reason, the files stay.
bool unreadable(const std::optional<Result<Snapshot>>& snapshot) {
  return snapshot && !*snapshot && !(*snapshot).error().is(ErrorKind::input_damaged);
}

void addDamage(RecoveredState& out, const std::string& what) {
  out.damage += (out.damage.empty() ? "" : "; ") + what;
}

}  // namespace

Result<RecoveredState> StateDirectory::readState(std::int64_t new_map_id,
                                                 std::optional<JournalContents>& resumable) const {
  RecoveredState out;
  auto newest = loadSnapshot(snapshotPath());
  if (unreadable(newest)) return newest->error();
  std::optional<Snapshot> snapshot;
  if (newest && *newest) {
    snapshot = std::move(**newest);
  } else {
    // No newest snapshot, or a damaged one: the previous generation and both journals.
    auto previous = loadSnapshot(previousSnapshotPath());
    if (unreadable(previous)) return previous->error();
    if (previous && !*previous) {
      if (newest) return Error::inputDamaged(newest->error().message + "; and " + previous->error().message);
      return previous->error();
    }
    if (newest && !previous) return newest->error();
    if (previous) {
      snapshot = std::move(**previous);
      out.snapshot_fallback = true;
      if (newest) {
        addDamage(out, newest->error().message + "; restored from the previous snapshot (seq " +
                           std::to_string(snapshot->seq) + ") and the journals");
        out.damaged_files.push_back(snapshotPath());
      }
      out.notes.push_back("restoring from " + previousSnapshotPath().string());
    }
  }
  if (snapshot) {
    out.map_id = snapshot->map_id;
    out.snapshot_seq = snapshot->seq;
    out.snapshot_map = std::move(snapshot->map_bytes);
    out.pages = std::move(snapshot->pages);
  }
  out.last_seq = out.snapshot_seq;

  std::vector<std::filesystem::path> journals;
  if (out.snapshot_fallback) journals.push_back(previousJournalPath());
  journals.push_back(journalPath());
  std::error_code ec;
  for (const auto& path : journals) {
    if (!std::filesystem::exists(path, ec)) continue;
    auto contents = readJournal(path);
    if (!contents && !contents.error().is(ErrorKind::input_damaged)) return contents.error();
    if (!contents) {
      // Nothing recoverable in it; kept aside all the same.
      addDamage(out, contents.error().message);
      out.damaged_files.push_back(path);
      out.notes.push_back(contents.error().message + "; the journal is started anew");
      continue;
    }
    const bool header_ok = contents->header_damage.empty();
    if (header_ok && out.map_id != 0 && contents->map_id != out.map_id) {
      out.notes.push_back(path.string() + ": belongs to map " + std::to_string(contents->map_id) +
                          ", the snapshot to map " + std::to_string(out.map_id) + "; the journal is ignored");
      continue;
    }
    if (header_ok && out.map_id == 0) out.map_id = contents->map_id;
    if (contents->torn_tail_offset)
      out.notes.push_back(path.string() + ": offset " + std::to_string(*contents->torn_tail_offset) + ": " +
                          contents->torn_tail_reason + "; the torn tail is cut");
    bool damaged = false;
    if (!header_ok) {
      damaged = true;
      addDamage(out, path.string() + ": offset 0: " + contents->header_damage);
    }
    for (const auto& d : contents->damaged) {
      damaged = true;
      addDamage(out, path.string() + ": offset " + std::to_string(d.offset) + ": " + d.reason + "; " +
                         std::to_string(d.length) + " bytes skipped, the whole records after them recovered");
    }
    if (damaged) out.damaged_files.push_back(path);
    if (header_ok && contents->base_seq > out.last_seq)
      addDamage(out, path.string() + ": continues seq " + std::to_string(contents->base_seq) + ", the records after " +
                         std::to_string(out.last_seq) + " before it are lost");
    std::size_t skipped = 0;
    bool first = true;
    for (auto& rec : contents->records) {
      if (rec.seq <= out.last_seq) {
        ++skipped;
        continue;
      }
      // Without its header a journal proves it continues this map only by its first new record.
      if (first && !header_ok && rec.seq != out.last_seq + 1) {
        addDamage(out, path.string() + ": its records from seq " + std::to_string(rec.seq) + " do not continue seq " +
                           std::to_string(out.last_seq) + " and are not replayed");
        break;
      }
      first = false;
      out.last_seq = rec.seq;
      out.replay.push_back(std::move(rec));
    }
    if (skipped != 0)
      out.notes.push_back(std::to_string(skipped) + " journal records already in the snapshot were skipped");
    if (!out.snapshot_fallback && !damaged && skipped == 0 && out.snapshot_seq == contents->base_seq)
      resumable = std::move(*contents);
  }
  if (out.map_id == 0) out.map_id = new_map_id;
  return out;
}

Status StateDirectory::journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements) {
  if (!writer_) return Error::internal(dir_.string() + ": no journal open (recover() first)");
  if (auto st = writer_->append(seq, utime, measurements); !st) return st;
  if (auto st = writer_->flush(); !st) return st;
  // While a snapshot is written, the journal that will continue it gets the record too.
  if (next_writer_) {
    if (auto st = next_writer_->append(seq, utime, measurements); !st) return st;
    return next_writer_->flush();
  }
  return okStatus();
}

namespace {

// `to` names the file `from` names now (a hard link, or a copy where the file system has none), replacing
// what `to` named, atomically.
Status keepAs(const std::filesystem::path& from, const std::filesystem::path& to) {
  const std::filesystem::path tmp = to.string() + ".tmp";
  std::error_code ec;
  std::filesystem::remove(tmp, ec);
  if (::link(from.c_str(), tmp.c_str()) != 0) {
    const auto raw = readWholeFile(from);
    if (!raw) return raw.error();
    return writeFileAtomically(to, *raw);
  }
  std::filesystem::rename(tmp, to, ec);
  if (ec) return Error::system(to.string() + ": cannot replace", ec);
  return okStatus();
}

}  // namespace

Status StateDirectory::snapshot(std::int64_t seq, std::span<const std::uint8_t> map_bytes,
                                std::span<const std::string> pages) {
  if (auto st = beginSnapshot(seq); !st) return st;
  if (auto st = writeSnapshotFile(snapshotPath(), map_id_, seq, map_bytes, pages); !st) {
    abandonSnapshot();
    return st;
  }
  retireOldJournal(retiredJournalPath());
  return finishSnapshot(pages);
}

Status StateDirectory::beginSnapshot(std::int64_t seq) {
  abandonSnapshot();
  // The current generation becomes the previous one: a damaged new snapshot then falls back to it and
  // the two journals. A crash in between leaves both names on the same files, which recovery reads alike;
  // the snapshot goes first, so that the previous journal then still reaches it. The journal goes on
  // growing under both names until finishSnapshot (a hard link), or the copy ends at the cut; either
  // way it reaches the new snapshot.
  std::error_code ec;
  if (std::filesystem::exists(snapshotPath(), ec) && std::filesystem::exists(journalPath(), ec)) {
    if (auto st = keepAs(snapshotPath(), previousSnapshotPath()); !st) return st;
    // The journal before it is only renamed here: freeing the blocks of a long journal takes a while, so
    // retireOldJournal() deletes it later, off the mapping thread. Meanwhile journal.ogfj continues the
    // snapshot that is now also the previous one, so nothing is missing from either generation.
    std::filesystem::rename(previousJournalPath(), retiredJournalPath(), ec);
    if (auto st = keepAs(journalPath(), previousJournalPath()); !st) return st;
  }
  auto w = JournalWriter::create(nextJournalPath(), map_id_, seq);
  if (!w) return w.error();
  next_writer_.emplace(std::move(*w));
  return okStatus();
}

Status StateDirectory::writeSnapshotFile(const std::filesystem::path& path, std::int64_t map_id, std::int64_t seq,
                                         std::span<const std::uint8_t> map_bytes,
                                         std::span<const std::string> pages) {
  return writeFileAtomically(path, encodeSnapshot(map_id, seq, map_bytes, pages));
}

void StateDirectory::retireOldJournal(const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);  // none there, or it cannot go: it is tried again at the next snapshot
}

Status StateDirectory::finishSnapshot(std::span<const std::string> pages) {
  if (!next_writer_) return Error::internal(dir_.string() + ": no snapshot begun");
  const std::filesystem::path journal = journalPath();
  std::error_code ec;
  std::filesystem::rename(nextJournalPath(), journal, ec);
  if (ec) return Error::system(journal.string() + ": cannot replace the journal", ec);
  syncParentDirectory(journal);  // records flushed from now on are found under this name after a power cut
  next_writer_->renamedTo(journal);  // so a later write error names the file that is there
  writer_ = std::move(next_writer_);
  next_writer_.reset();
  previous_pages_ = std::move(current_pages_);
  current_pages_.assign(pages.begin(), pages.end());
  return okStatus();
}

void StateDirectory::abandonSnapshot() {
  if (!next_writer_) return;
  next_writer_.reset();
  std::error_code ec;
  std::filesystem::remove(nextJournalPath(), ec);
}

std::vector<std::string> StateDirectory::referencedPages() const {
  std::vector<std::string> names = current_pages_;
  names.insert(names.end(), previous_pages_.begin(), previous_pages_.end());
  return names;
}

}  // namespace ogf::persistence
