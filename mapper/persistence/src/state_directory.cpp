#include "ogf/persistence/state_directory.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "ogf/common/atomic_file.hpp"
#include "ogf/common/crc32.hpp"
#include "ogf/common/little_endian.hpp"

namespace ogf::persistence {
namespace {

constexpr char kMagic[8] = {'O', 'G', 'F', 'S', 'N', 'A', 'P', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kFixed = 8 + 4 + 8 + 8 + 8;

template <class T>
void put(std::vector<std::byte>& out, T v) {
  putLittleEndian(out, v);
}

template <class T>
T get(const std::byte* p) {
  return getLittleEndian<T>(p);
}

}  // namespace

std::vector<std::byte> encodeSnapshot(std::int64_t map_id, std::int64_t seq, std::span<const std::uint8_t> map_bytes) {
  std::vector<std::byte> out;
  out.reserve(kFixed + map_bytes.size() + 4);
  for (char c : kMagic) out.push_back(static_cast<std::byte>(c));
  put<std::uint32_t>(out, kVersion);
  put<std::int64_t>(out, map_id);
  put<std::int64_t>(out, seq);
  put<std::uint64_t>(out, map_bytes.size());
  for (std::uint8_t b : map_bytes) out.push_back(static_cast<std::byte>(b));
  put<std::uint32_t>(out, crc32(out.data(), out.size()));
  return out;
}

Result<Snapshot> decodeSnapshot(std::span<const std::byte> bytes, const std::string& source) {
  if (bytes.size() < kFixed + 4) return Error{source + ": offset 0: snapshot truncated (" + std::to_string(bytes.size()) + " bytes)"};
  if (std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) return Error{source + ": offset 0: not an ogf snapshot (bad magic)"};
  if (const auto v = get<std::uint32_t>(bytes.data() + 8); v != kVersion)
    return Error{source + ": offset 8: unsupported snapshot version " + std::to_string(v)};
  const auto n = get<std::uint64_t>(bytes.data() + 28);
  if (n != bytes.size() - kFixed - 4)
    return Error{source + ": offset 28: map length " + std::to_string(n) + " does not match the file (" +
                 std::to_string(bytes.size() - kFixed - 4) + " bytes follow): truncated or corrupt"};
  if (get<std::uint32_t>(bytes.data() + bytes.size() - 4) != crc32(bytes.data(), bytes.size() - 4))
    return Error{source + ": offset " + std::to_string(bytes.size() - 4) + ": snapshot checksum mismatch"};
  Snapshot s;
  s.map_id = get<std::int64_t>(bytes.data() + 12);
  s.seq = get<std::int64_t>(bytes.data() + 20);
  s.map_bytes.resize(n);
  std::memcpy(s.map_bytes.data(), bytes.data() + kFixed, n);
  return s;
}

Result<StateDirectory> StateDirectory::open(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Error{dir.string() + ": cannot create the state directory: " + ec.message()};
  if (::access(dir.c_str(), W_OK) != 0)
    return Error{dir.string() + ": the state directory is not writable: " + std::strerror(errno)};
  return StateDirectory(dir);
}

Result<RecoveredState> StateDirectory::read(const std::filesystem::path& dir, std::int64_t new_map_id) {
  std::optional<JournalContents> resumable;
  return StateDirectory(dir).readState(new_map_id, resumable);
}

Result<RecoveredState> StateDirectory::recover(std::int64_t new_map_id) {
  std::optional<JournalContents> resumable;
  auto state = readState(new_map_id, resumable);
  if (!state) return state.error();
  RecoveredState& out = *state;
  map_id_ = out.map_id;
  writer_.reset();
  if (resumable) {
    // The journal continues the snapshot: keep appending to it.
    auto w = JournalWriter::resume(journalPath(), *resumable);
    if (!w) return w.error();
    writer_.emplace(std::move(*w));
  } else {
    // No journal to continue: write the replayed records into a fresh one after the snapshot, so the
    // directory again holds snapshot + journal = the map.
    auto w = JournalWriter::create(journalPath(), map_id_, out.snapshot_seq);
    if (!w) return w.error();
    writer_.emplace(std::move(*w));
    for (const auto& rec : out.replay)
      if (auto st = writer_->append(rec.seq, rec.utime, rec.measurements); !st) return st.error();
    if (auto st = writer_->flush(); !st) return st.error();
  }
  return state;
}

Result<RecoveredState> StateDirectory::readState(std::int64_t new_map_id,
                                                 std::optional<JournalContents>& resumable) const {
  RecoveredState out;
  std::error_code ec;
  if (std::filesystem::exists(snapshotPath(), ec)) {
    std::ifstream in(snapshotPath(), std::ios::binary);
    const std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto snap = decodeSnapshot(std::span(reinterpret_cast<const std::byte*>(raw.data()), raw.size()), snapshotPath().string());
    if (!snap) return snap.error();
    out.map_id = snap->map_id;
    out.snapshot_seq = snap->seq;
    out.snapshot_map = std::move(snap->map_bytes);
  }
  out.last_seq = out.snapshot_seq;

  if (std::filesystem::exists(journalPath(), ec)) {
    auto contents = readJournal(journalPath());
    if (!contents) {
      // A journal whose header is unreadable holds nothing recoverable: start a new one, say so.
      out.notes.push_back(contents.error().message + "; the journal is started anew");
    } else if (out.map_id != 0 && contents->map_id != out.map_id) {
      out.notes.push_back(journalPath().string() + ": belongs to map " + std::to_string(contents->map_id) +
                          ", the snapshot to map " + std::to_string(out.map_id) + "; the journal is ignored");
    } else {
      if (out.map_id == 0) out.map_id = contents->map_id;
      if (contents->torn_tail_offset)
        out.notes.push_back(journalPath().string() + ": offset " + std::to_string(*contents->torn_tail_offset) +
                            ": " + contents->torn_tail_reason + "; the torn tail is cut");
      std::size_t skipped = 0;
      for (auto& rec : contents->records) {
        if (rec.seq <= out.last_seq) {
          ++skipped;
          continue;
        }
        out.last_seq = rec.seq;
        out.replay.push_back(std::move(rec));
      }
      if (skipped != 0)
        out.notes.push_back(std::to_string(skipped) + " journal records already in the snapshot were skipped");
      if (skipped == 0 && out.snapshot_seq == contents->base_seq) resumable = std::move(*contents);
    }
  }
  if (out.map_id == 0) out.map_id = new_map_id;
  return out;
}

Status StateDirectory::journal(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements) {
  if (!writer_) return Error{dir_.string() + ": no journal open (recover() first)"};
  if (auto st = writer_->append(seq, utime, measurements); !st) return st;
  return writer_->flush();
}

Status StateDirectory::snapshot(std::int64_t seq, std::span<const std::uint8_t> map_bytes) {
  const auto bytes = encodeSnapshot(map_id_, seq, map_bytes);
  if (auto st = writeFileAtomically(snapshotPath(), bytes); !st) return st;
  const std::filesystem::path journal = journalPath();
  const std::filesystem::path fresh = journal.string() + ".new";
  auto w = JournalWriter::create(fresh, map_id_, seq);
  if (!w) return w.error();
  std::error_code ec;
  std::filesystem::rename(fresh, journal, ec);
  if (ec) return Error{journal.string() + ": cannot replace the journal: " + ec.message()};
  w->renamedTo(journal);  // so a later write error names the file that is there
  writer_.emplace(std::move(*w));
  return okStatus();
}

}  // namespace ogf::persistence
