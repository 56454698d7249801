#include "ogf/persistence/journal.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <limits>

#include "ogf/common/atomic_file.hpp"
#include "ogf/common/crc32.hpp"
#include "ogf/common/little_endian.hpp"
#include "ogf/common/read_file.hpp"
#include "ogf/persistence/measurement_coding.hpp"

namespace ogf::persistence {
namespace {

constexpr char kJournalMagic[8] = {'O', 'G', 'F', 'J', 'R', 'N', 'L', '1'};
constexpr std::uint32_t kJournalVersion = 2;
constexpr std::uint32_t kFixedVersion = 1;  // still read: every record's measurements in 13 bytes
constexpr std::uint32_t kFixedRecordMagic = 0x4352524A;  // "JRRC"
constexpr std::uint32_t kCodedRecordMagic2 = 0x3243524A;  // "JRC2": still read; coding version 2
constexpr std::uint32_t kCodedRecordMagic = 0x3343524A;   // "JRC3": coding version 3
constexpr std::size_t kHeaderSize = 8 + 4 + 8 + 8 + 4;
constexpr std::size_t kFixedRecordFixed = 4 + 4 + 8 + 8;      // before the measurements
constexpr std::size_t kCodedRecordFixed = 4 + 4 + 8 + 8 + 4;  // and the length of their coding
constexpr std::size_t kMeasurementSize = 13;
// A record holds one scan's measurement set; 2^24 is far above any (a VLP-16 scan at 0.1 m makes ~1 M).
constexpr std::uint32_t kMaxMeasurements = 1U << 24;

Error systemError(const std::filesystem::path& path, const std::string& what) {
  const int e = errno;
  return Error::system(path.string() + ": " + what, e);
}

std::vector<std::byte> header(std::int64_t map_id, std::int64_t base_seq) {
  std::vector<std::byte> h;
  for (char c : kJournalMagic) h.push_back(static_cast<std::byte>(c));
  putLittleEndian<std::uint32_t>(h, kJournalVersion);
  putLittleEndian<std::int64_t>(h, map_id);
  putLittleEndian<std::int64_t>(h, base_seq);
  putLittleEndian<std::uint32_t>(h, crc32(h.data(), h.size()));
  return h;
}

Status writeWhole(int fd, const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  if (writeAll(fd, bytes) != bytes.size()) return systemError(path, "write failed");
  return okStatus();
}

}  // namespace

namespace {

bool isRecordMagic(std::uint32_t magic) {
  return magic == kFixedRecordMagic || magic == kCodedRecordMagic2 || magic == kCodedRecordMagic;
}

// The record at `off` when it is whole (magic, length within the file, checksum, measurements that decode
// into `rec`), else why not.
struct RecordAt {
  std::size_t length = 0;  // 0: not a whole record
  std::string why;
};

RecordAt recordAt(const std::byte* data, std::size_t size, std::size_t off, JournalRecord& rec) {
  if (size - off < kFixedRecordFixed + 4) return {0, "record header truncated"};
  const std::byte* r = data + off;
  const auto magic = getLittleEndian<std::uint32_t>(r);
  if (!isRecordMagic(magic)) return {0, "bad record magic"};
  const auto n = getLittleEndian<std::uint32_t>(r + 4);
  if (n > kMaxMeasurements) return {0, "absurd measurement count " + std::to_string(n)};
  const bool coded = magic != kFixedRecordMagic;
  std::size_t len = kFixedRecordFixed + static_cast<std::size_t>(n) * kMeasurementSize + 4;
  if (coded) {
    if (size - off < kCodedRecordFixed + 4) return {0, "record header truncated"};
    const auto coding = getLittleEndian<std::uint32_t>(r + kFixedRecordFixed);
    if (coding > static_cast<std::size_t>(n) * kMaxCodedMeasurement)
      return {0, "absurd coding length " + std::to_string(coding) + " for " + std::to_string(n) + " measurements"};
    len = kCodedRecordFixed + coding + 4;
  }
  if (size - off < len) return {0, "record truncated"};
  if (getLittleEndian<std::uint32_t>(r + len - 4) != crc32(r, len - 4)) return {0, "record checksum mismatch"};
  rec.seq = getLittleEndian<std::int64_t>(r + 8);
  rec.utime = getLittleEndian<std::int64_t>(r + 16);
  rec.offset = off;
  if (coded) {
    const CodingVersion version = magic == kCodedRecordMagic2 ? CodingVersion::k2 : CodingVersion::k3;
    if (!decodeMeasurements(std::span(r + kCodedRecordFixed, len - 4 - kCodedRecordFixed), n,
                            rec.measurements, version))
      return {0, "measurements not in the journal's coding"};
    return {len, ""};
  }
  rec.measurements.resize(n);
  const std::byte* m = r + kFixedRecordFixed;
  for (std::uint32_t i = 0; i < n; ++i, m += kMeasurementSize) {
    const CellKey key{getLittleEndian<std::int32_t>(m), getLittleEndian<std::int32_t>(m + 4),
                      getLittleEndian<std::int32_t>(m + 8)};
    rec.measurements[i] = Measurement{key, getLittleEndian<std::int8_t>(m + 12)};
  }
  return {len, ""};
}

std::string headerDamage(const std::byte* data) {
  if (std::memcmp(data, kJournalMagic, sizeof(kJournalMagic)) != 0) return "not an ogf journal (bad magic)";
  if (getLittleEndian<std::uint32_t>(data + kHeaderSize - 4) != crc32(data, kHeaderSize - 4))
    return "journal header checksum mismatch";
  if (const auto v = getLittleEndian<std::uint32_t>(data + 8); v != kJournalVersion && v != kFixedVersion)
    return "unsupported journal version " + std::to_string(v);
  return "";
}

}  // namespace

Result<JournalContents> readJournal(const std::filesystem::path& path) {
  const auto raw = readWholeFile(path);
  if (!raw) return raw.error();
  const std::byte* data = raw->data();
  const std::size_t size = raw->size();

  if (size < kHeaderSize) return Error::inputDamaged(path.string() + ": offset 0: journal header truncated (" + std::to_string(size) + " bytes)");
  JournalContents out;
  out.header_damage = headerDamage(data);
  if (out.header_damage.empty()) {
    out.map_id = getLittleEndian<std::int64_t>(data + 12);
    out.base_seq = getLittleEndian<std::int64_t>(data + 20);
  }
  // Records follow each other; a stretch that is not a whole record (or whose sequence does not increase)
  // is skipped up to the next whole record, whose magic and checksum make a false match implausible.
  std::int64_t last_seq = out.header_damage.empty() ? out.base_seq : std::numeric_limits<std::int64_t>::min();
  std::size_t off = kHeaderSize;
  JournalRecord rec;
  while (off < size) {
    RecordAt at = recordAt(data, size, off, rec);
    if (at.length != 0 && rec.seq <= last_seq)
      at = {0, "sequence " + std::to_string(rec.seq) + " does not increase"};
    if (at.length != 0) {
      last_seq = rec.seq;
      out.records.push_back(std::move(rec));
      rec = {};
      off += at.length;
      continue;
    }
    std::size_t next = off + 1;
    for (; next < size; ++next) {
      if (size - next < kFixedRecordFixed + 4) {
        next = size;
        break;
      }
      if (!isRecordMagic(getLittleEndian<std::uint32_t>(data + next))) continue;
      const RecordAt candidate = recordAt(data, size, next, rec);
      if (candidate.length != 0 && rec.seq > last_seq) break;
    }
    if (next >= size) {
      out.torn_tail_offset = off;
      out.torn_tail_reason = at.why;
      break;
    }
    out.damaged.push_back({off, next - off, at.why});
    off = next;
  }
  if (!out.header_damage.empty() && out.records.empty())
    return Error::inputDamaged(path.string() + ": offset 0: " + out.header_damage + ", and no whole record follows");
  return out;
}

Result<JournalWriter> JournalWriter::create(const std::filesystem::path& path, std::int64_t map_id,
                                            std::int64_t base_seq) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return systemError(path, "cannot create journal");
  const auto h = header(map_id, base_seq);
  if (auto st = writeWhole(fd, path, h); !st) {
    ::close(fd);
    return st.error();
  }
  if (::fdatasync(fd) != 0) {
    auto err = systemError(path, "fdatasync failed");
    ::close(fd);
    return err;
  }
  return JournalWriter(path, fd, h.size(), base_seq);
}

Result<JournalWriter> JournalWriter::resume(const std::filesystem::path& path, const JournalContents& contents) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return systemError(path, "cannot open journal");
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    auto err = systemError(path, "fstat failed");
    ::close(fd);
    return err;
  }
  auto end = static_cast<std::uint64_t>(st.st_size);
  if (contents.torn_tail_offset) {
    end = *contents.torn_tail_offset;
    if (::ftruncate(fd, static_cast<off_t>(end)) != 0 || ::fdatasync(fd) != 0) {
      auto err = systemError(path, "cannot cut the torn tail");
      ::close(fd);
      return err;
    }
  }
  if (::lseek(fd, static_cast<off_t>(end), SEEK_SET) < 0) {
    auto err = systemError(path, "lseek failed");
    ::close(fd);
    return err;
  }
  const std::int64_t last = contents.records.empty() ? contents.base_seq : contents.records.back().seq;
  return JournalWriter(path, fd, end, last);
}

JournalWriter::JournalWriter(JournalWriter&& o) noexcept
    : path_(std::move(o.path_)), fd_(o.fd_), size_(o.size_), last_seq_(o.last_seq_), pending_(std::move(o.pending_)) {
  o.fd_ = -1;
}

JournalWriter& JournalWriter::operator=(JournalWriter&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(o.path_);
    fd_ = o.fd_;
    size_ = o.size_;
    last_seq_ = o.last_seq_;
    pending_ = std::move(o.pending_);
    o.fd_ = -1;
  }
  return *this;
}

JournalWriter::~JournalWriter() {
  if (fd_ >= 0) ::close(fd_);
}

Status JournalWriter::append(std::int64_t seq, std::int64_t utime, std::span<const Measurement> measurements) {
  if (seq <= last_seq_)
    return Error::internal(path_.string() + ": record seq " + std::to_string(seq) + " after " + std::to_string(last_seq_));
  if (measurements.size() > kMaxMeasurements)
    return Error::resource(path_.string() + ": record of " + std::to_string(measurements.size()) + " measurements is too large");
  const std::size_t start = pending_.size();
  putLittleEndian<std::uint32_t>(pending_, kCodedRecordMagic);
  putLittleEndian<std::uint32_t>(pending_, static_cast<std::uint32_t>(measurements.size()));
  putLittleEndian<std::int64_t>(pending_, seq);
  putLittleEndian<std::int64_t>(pending_, utime);
  putLittleEndian<std::uint32_t>(pending_, 0);  // the coding's length, known once it is written
  const std::size_t coding = pending_.size();
  encodeMeasurements(measurements, pending_);
  const auto length = static_cast<std::uint32_t>(pending_.size() - coding);
  std::vector<std::byte> field;
  putLittleEndian<std::uint32_t>(field, length);
  std::copy(field.begin(), field.end(), pending_.begin() + static_cast<std::ptrdiff_t>(coding - 4));
  putLittleEndian<std::uint32_t>(pending_, crc32(pending_.data() + start, pending_.size() - start));
  last_seq_ = seq;
  return okStatus();
}

Status JournalWriter::flush() {
  if (pending_.empty()) return okStatus();
  if (fd_ < 0) return Error::internal(path_.string() + ": journal is closed");
  if (auto st = writeWhole(fd_, path_, pending_); !st) {
    // A partial write (disk full) must not leave half a record: cut back to the last whole one so a
    // later flush (which retries the whole buffer) continues a readable journal.
    if (::ftruncate(fd_, static_cast<off_t>(size_)) == 0) ::lseek(fd_, static_cast<off_t>(size_), SEEK_SET);
    return st;
  }
  if (::fdatasync(fd_) != 0) return systemError(path_, "fdatasync failed");
  size_ += pending_.size();
  pending_.clear();
  return okStatus();
}

}  // namespace ogf::persistence
