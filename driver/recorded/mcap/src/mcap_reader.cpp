#include "ogf/mcap/mcap_reader.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <optional>
#include <queue>

#include "ogf/mcap/chunk_codec.hpp"

namespace ogf::mcap {
namespace {

// The bytes a chunk's fields before its records take at most: three uint64, a uint32, a compression name
// of at most 64 bytes with its length, and the records' uint64 length.
constexpr std::size_t kChunkHeaderMaxBytes = 8 + 8 + 8 + 4 + 4 + 64 + 8;
// Names kept of all schemas and channels together; beyond, further ones are refused as damage.
constexpr std::uint64_t kMaxNamesBytes = std::uint64_t{16} << 20;

std::uint64_t channelBit(std::uint16_t id) { return std::uint64_t{1} << (id % 64); }

std::uint64_t little(const std::uint8_t* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * i);
  return v;
}

const char* opcodeName(std::uint8_t op) {
  switch (static_cast<Opcode>(op)) {
    case Opcode::header:
      return "Header";
    case Opcode::footer:
      return "Footer";
    case Opcode::schema:
      return "Schema";
    case Opcode::channel:
      return "Channel";
    case Opcode::message:
      return "Message";
    case Opcode::chunk:
      return "Chunk";
    case Opcode::message_index:
      return "Message Index";
    case Opcode::chunk_index:
      return "Chunk Index";
    case Opcode::attachment:
      return "Attachment";
    case Opcode::attachment_index:
      return "Attachment Index";
    case Opcode::statistics:
      return "Statistics";
    case Opcode::metadata:
      return "Metadata";
    case Opcode::metadata_index:
      return "Metadata Index";
    case Opcode::summary_offset:
      return "Summary Offset";
    case Opcode::data_end:
      return "Data End";
  }
  return op >= 0x80 ? "private" : "unknown";
}

// Walks the records of `bytes` (a chunk's records or the summary section); `record` gets each opcode, content
// and the offset of its prefix. An error names the offset of the record that does not fit.
template <class Record>
Status forEachRecord(std::span<const std::uint8_t> bytes, Record record) {
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    if (bytes.size() - pos < kRecordPrefixBytes)
      return Error::inputDamaged(
          fmt::format("{} bytes at byte {} are no whole record", bytes.size() - pos, pos));
    const std::uint8_t op = bytes[pos];
    const std::uint64_t length = little(&bytes[pos + 1], 8);
    if (op == 0) return Error::inputDamaged(fmt::format("byte {} holds opcode 0, which is no record", pos));
    if (length > bytes.size() - pos - kRecordPrefixBytes)
      return Error::inputDamaged(fmt::format("the {} record at byte {} claims {} bytes, {} are left",
                                             opcodeName(op), pos, length,
                                             bytes.size() - pos - kRecordPrefixBytes));
    if (auto st = record(op, bytes.subspan(pos + kRecordPrefixBytes, length), pos); !st) return st;
    pos += kRecordPrefixBytes + length;
  }
  return okStatus();
}

}  // namespace

// One message to visit from a held unit: where its record's content lies in the unit's bytes.
struct HeldEntry {
  std::uint64_t log_time;
  std::size_t content;
  std::size_t size;
};

// A unit read and decoded, whose messages wait their turn.
struct HeldUnit {
  std::uint64_t offset = 0;  // the unit's, for the order of equal times
  bool chunk = true;
  std::vector<std::uint8_t> bytes;
  std::vector<HeldEntry> entries;  // in log-time order
  std::size_t next = 0;
};

McapReader::~McapReader() {
  if (fd_ >= 0) ::close(fd_);
}

McapReader::McapReader(McapReader&& o) noexcept
    : path_(std::move(o.path_)),
      fd_(std::exchange(o.fd_, -1)),
      profile_(std::move(o.profile_)),
      indexed_(o.indexed_),
      channels_(std::move(o.channels_)),
      channel_index_(std::move(o.channel_index_)),
      schemas_(std::move(o.schemas_)),
      units_(std::move(o.units_)),
      damage_(std::move(o.damage_)),
      names_bytes_(o.names_bytes_) {}

McapReader& McapReader::operator=(McapReader&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    path_ = std::move(o.path_);
    fd_ = std::exchange(o.fd_, -1);
    profile_ = std::move(o.profile_);
    indexed_ = o.indexed_;
    channels_ = std::move(o.channels_);
    channel_index_ = std::move(o.channel_index_);
    schemas_ = std::move(o.schemas_);
    units_ = std::move(o.units_);
    damage_ = std::move(o.damage_);
    names_bytes_ = o.names_bytes_;
  }
  return *this;
}

Status McapReader::readAt(std::uint64_t offset, std::span<std::uint8_t> out) const {
  std::size_t done = 0;
  while (done < out.size()) {
    const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
    if (n < 0) {
      if (errno == EINTR) continue;
      return Error::system(fmt::format("{}: cannot read at byte {}", path_.string(), offset + done));
    }
    if (n == 0)
      return Error::inputDamaged(fmt::format("{}: the file ends at byte {}", path_.string(), offset + done));
    done += static_cast<std::size_t>(n);
  }
  return okStatus();
}

std::string McapReader::at(const Unit& unit) const {
  return fmt::format("{}: {} at byte {}", path_.string(), unit.chunk ? "chunk" : "message", unit.offset);
}

Result<McapReader> McapReader::open(const std::filesystem::path& file) {
  McapReader r;
  r.path_ = file;
  r.fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (r.fd_ < 0) return Error::system(file.string() + ": cannot open");
  struct stat st {};
  if (::fstat(r.fd_, &st) != 0) return Error::system(file.string() + ": cannot stat");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  std::array<std::uint8_t, kMagic.size() + kRecordPrefixBytes> start{};
  if (size < start.size() || !r.readAt(0, start) || !std::equal(kMagic.begin(), kMagic.end(), start.begin()))
    return Error::inputDamaged(file.string() + ": not an MCAP file (no MCAP magic at its start)");
  const std::uint64_t header_length = little(&start[kMagic.size() + 1], 8);
  if (start[kMagic.size()] != static_cast<std::uint8_t>(Opcode::header) || header_length > kMaxRecordBytes ||
      header_length > size - start.size())
    return Error::inputDamaged(file.string() + ": not an MCAP file (no Header record after the magic)");
  std::vector<std::uint8_t> header(header_length);
  if (auto st2 = r.readAt(start.size(), header); !st2) return st2.error();
  auto h = parseHeader(header);
  if (!h) return h.error().within(file.string() + ": byte 8");
  r.profile_ = h->profile;

  auto summary = r.readSummary(size);
  if (!summary)
    r.damage_.push_back(summary.error().message + "; reading the data section from the start instead");
  if (!summary || !*summary) {
    r.channels_.clear();
    r.channel_index_.clear();
    r.schemas_.clear();
    r.units_.clear();
    r.names_bytes_ = 0;
    r.scan(size);
  }
  r.indexed_ = summary && *summary;
  return r;
}

void McapReader::addSchema(const Schema& s) {
  if (s.id == 0) return;  // "A Schema record with an id of zero is invalid and should be ignored"
  if (schemas_.contains(s.id)) return;
  names_bytes_ += s.name.size() + s.encoding.size();
  if (names_bytes_ > kMaxNamesBytes) {
    damage_.push_back(fmt::format("{}: schema {}: more schema and channel names than {} bytes; not kept",
                                  path_.string(), s.id, kMaxNamesBytes));
    return;
  }
  schemas_[s.id] = {s.name, s.encoding};
}

void McapReader::addChannel(const Channel& c) {
  if (channel_index_.contains(c.id)) return;
  names_bytes_ += c.topic.size() + c.message_encoding.size();
  if (names_bytes_ > kMaxNamesBytes) {
    damage_.push_back(
        fmt::format("{}: channel {} ({}): more schema and channel names than {} bytes; not kept",
                    path_.string(), c.id, c.topic, kMaxNamesBytes));
    return;
  }
  ChannelInfo info;
  info.id = c.id;
  info.topic = c.topic;
  info.message_encoding = c.message_encoding;
  if (const auto s = schemas_.find(c.schema_id); s != schemas_.end()) {
    info.schema_name = s->second.name;
    info.schema_encoding = s->second.encoding;
  }
  channel_index_[c.id] = channels_.size();
  channels_.push_back(std::move(info));
}

Result<bool> McapReader::readSummary(std::uint64_t size) {
  if (size < kMagic.size() * 2 + kFooterRecordBytes) return false;
  const std::uint64_t footer_at = size - kMagic.size() - kFooterRecordBytes;
  std::array<std::uint8_t, kFooterRecordBytes + kMagic.size()> tail{};
  if (!readAt(footer_at, tail)) return false;
  if (!std::equal(kMagic.begin(), kMagic.end(), tail.begin() + kFooterRecordBytes))
    return false;  // cut short
  if (tail[0] != static_cast<std::uint8_t>(Opcode::footer) || little(&tail[1], 8) != kFooterContentBytes)
    return false;
  auto footer = parseFooter(std::span(tail).subspan(kRecordPrefixBytes, kFooterContentBytes));
  if (!footer || footer->summary_start == 0) return false;
  const std::string where =
      fmt::format("{}: summary section at byte {}", path_.string(), footer->summary_start);
  if (footer->summary_start < kMagic.size() || footer->summary_start > footer_at)
    return Error::inputDamaged(fmt::format("{}: the footer puts it outside the file", where));
  if (footer_at - footer->summary_start > kMaxRecordBytes) return false;
  std::vector<std::uint8_t> summary(footer_at - footer->summary_start);
  if (auto st = readAt(footer->summary_start, summary); !st) return st.error();
  if (footer->summary_crc != 0) {
    // "A CRC32 of all bytes from the start of the Summary section up through and including the end of the
    // previous field (summary_offset_start) in the footer record."
    const std::uint32_t crc = crc32(std::span(tail).first(kRecordPrefixBytes + 16), crc32(summary));
    if (crc != footer->summary_crc)
      return Error::inputDamaged(
          fmt::format("{}: CRC-32 {:08x}, the footer says {:08x}", where, crc, footer->summary_crc));
  }
  std::vector<Channel> channels;
  std::optional<Statistics> stats;
  auto st = forEachRecord(
      summary, [&](std::uint8_t op, std::span<const std::uint8_t> content, std::size_t pos) -> Status {
        const auto fail = [&](const Error& e) {
          return e.within(fmt::format("{}: byte {} of it", where, pos));
        };
        switch (static_cast<Opcode>(op)) {
          case Opcode::schema: {
            auto s = parseSchema(content);
            if (!s) return fail(s.error());
            addSchema(*s);
            break;
          }
          case Opcode::channel: {
            auto c = parseChannel(content);
            if (!c) return fail(c.error());
            channels.push_back(std::move(*c));
            break;
          }
          case Opcode::chunk_index: {
            auto c = parseChunkIndex(content);
            if (!c) return fail(c.error());
            if (c->chunk_start_offset < kMagic.size() || c->chunk_length < kRecordPrefixBytes ||
                c->chunk_start_offset > footer->summary_start ||
                c->chunk_length > footer->summary_start - c->chunk_start_offset)
              return fail(Error::inputDamaged(
                  fmt::format("a Chunk Index puts its chunk at byte {} ({} bytes), outside the data section",
                              c->chunk_start_offset, c->chunk_length)));
            if (units_.size() >= kMaxChunks)
              return fail(Error::inputDamaged(fmt::format("more than {} chunks", kMaxChunks)));
            Unit u;
            u.offset = c->chunk_start_offset;
            u.length = c->chunk_length;
            u.start = c->message_start_time;
            u.end = c->message_end_time;
            if (!c->channel_ids.empty()) {
              u.channel_mask = 0;
              for (const std::uint16_t id : c->channel_ids) u.channel_mask |= channelBit(id);
            }
            units_.push_back(std::move(u));
            break;
          }
          case Opcode::statistics: {
            auto s = parseStatistics(content);
            if (!s) return fail(s.error());
            stats = std::move(*s);
            break;
          }
          default:
            break;
        }
        return okStatus();
      });
  if (!st) return st.error();
  for (const Channel& c : channels) addChannel(c);
  // Usable only when it covers every message: statistics with the channels' counts and an index of every
  // chunk (messages outside chunks are not indexed).
  if (!stats) return false;
  if (stats->message_count > 0 && (stats->channel_message_counts.empty() || units_.empty())) return false;
  if (stats->chunk_count != units_.size()) return false;
  for (const auto& [id, count] : stats->channel_message_counts)
    if (const auto it = channel_index_.find(id); it != channel_index_.end())
      channels_[it->second].message_count = count;
  return true;
}

void McapReader::scan(std::uint64_t size) {
  std::uint64_t pos = kMagic.size();
  const auto cut = [&](const std::string& why) {
    damage_.push_back(fmt::format("{}: {}; what comes before it is read", path_.string(), why));
  };
  while (pos < size) {
    std::array<std::uint8_t, kRecordPrefixBytes> prefix{};
    if (size - pos < kRecordPrefixBytes) {
      if (size - pos != kMagic.size())
        cut(fmt::format("the file ends {} bytes after byte {}, inside a record", size - pos, pos));
      return;
    }
    if (!readAt(pos, prefix)) return cut(fmt::format("cannot read the record at byte {}", pos));
    const std::uint8_t op = prefix[0];
    const std::uint64_t length = little(&prefix[1], 8);
    if (op == 0)
      return cut(fmt::format("byte {} holds opcode 0, which is no record: the rest is not read", pos));
    if (length > size - pos - kRecordPrefixBytes)
      return cut(
          fmt::format("the {} record at byte {} claims {} bytes, the file ends {} bytes after it: cut short",
                      opcodeName(op), pos, length, size - pos - kRecordPrefixBytes));
    const std::uint64_t next = pos + kRecordPrefixBytes + length;
    const auto bad = [&](const std::string& why) {
      damage_.push_back(
          fmt::format("{}: {} record at byte {}: {}; skipped", path_.string(), opcodeName(op), pos, why));
    };
    switch (static_cast<Opcode>(op)) {
      case Opcode::footer:
      case Opcode::data_end:
        return;  // the summary follows, which this walk does not need
      case Opcode::schema:
      case Opcode::channel: {
        if (length > kMaxRecordBytes) {
          bad(fmt::format("{} bytes, more than the {} allowed", length, kMaxRecordBytes));
          break;
        }
        std::vector<std::uint8_t> content(length);
        if (!readAt(pos + kRecordPrefixBytes, content)) return cut(fmt::format("cannot read byte {}", pos));
        if (static_cast<Opcode>(op) == Opcode::schema) {
          auto s = parseSchema(content);
          if (!s)
            bad(s.error().message);
          else
            addSchema(*s);
        } else {
          auto c = parseChannel(content);
          if (!c)
            bad(c.error().message);
          else
            addChannel(*c);
        }
        break;
      }
      case Opcode::message: {
        std::array<std::uint8_t, kMessageHeaderBytes> head{};
        if (length < head.size()) {
          bad("shorter than a message's fields");
          break;
        }
        if (!readAt(pos + kRecordPrefixBytes, head)) return cut(fmt::format("cannot read byte {}", pos));
        auto m = parseMessage(head, nullptr);
        if (units_.size() >= kMaxChunks)
          return cut(fmt::format("more than {} chunks and messages outside chunks", kMaxChunks));
        Unit u;
        u.offset = pos;
        u.length = kRecordPrefixBytes + length;
        u.start = u.end = m->log_time;
        u.chunk = false;
        u.channel_mask = channelBit(m->channel_id);
        if (const auto it = channel_index_.find(m->channel_id); it != channel_index_.end())
          ++channels_[it->second].message_count;
        units_.push_back(std::move(u));
        break;
      }
      case Opcode::chunk: {
        if (units_.size() >= kMaxChunks)
          return cut(fmt::format("more than {} chunks and messages outside chunks", kMaxChunks));
        Unit u;
        u.offset = pos;
        u.length = kRecordPrefixBytes + length;
        scanChunk(u);
        units_.push_back(std::move(u));
        break;
      }
      default:
        break;  // indexes, attachments, metadata and private records: not needed to read the messages
    }
    pos = next;
  }
}

void McapReader::scanChunk(Unit& unit) {
  auto records = readUnit(unit);
  if (!records) {
    unit.damaged = records.error().message;
    unit.channel_mask = ~std::uint64_t{0};
    return;
  }
  unit.channel_mask = 0;
  bool first = true;
  auto st = forEachRecord(
      *records, [&](std::uint8_t op, std::span<const std::uint8_t> content, std::size_t) -> Status {
        switch (static_cast<Opcode>(op)) {
          case Opcode::schema:
            if (auto s = parseSchema(content))
              addSchema(*s);
            else
              return s.error();
            break;
          case Opcode::channel:
            if (auto c = parseChannel(content))
              addChannel(*c);
            else
              return c.error();
            break;
          case Opcode::message: {
            auto m = parseMessage(content, nullptr);
            if (!m) return m.error();
            unit.channel_mask |= channelBit(m->channel_id);
            unit.start = first ? m->log_time : std::min(unit.start, m->log_time);
            unit.end = first ? m->log_time : std::max(unit.end, m->log_time);
            first = false;
            if (const auto it = channel_index_.find(m->channel_id); it != channel_index_.end())
              ++channels_[it->second].message_count;
            break;
          }
          default:
            break;
        }
        return okStatus();
      });
  // A record that does not parse: the messages before it count and will be read; reading reports it.
  (void)st;
}

Result<std::vector<std::uint8_t>> McapReader::readUnit(const Unit& unit) const {
  const std::uint64_t content_length = unit.length - kRecordPrefixBytes;
  if (!unit.chunk) {
    if (content_length > kMaxRecordBytes)
      return Error::inputDamaged(
          fmt::format("{}: {} bytes, more than the {} allowed", at(unit), content_length, kMaxRecordBytes));
    std::vector<std::uint8_t> content(content_length);
    if (auto st = readAt(unit.offset + kRecordPrefixBytes, content); !st) return st.error();
    return content;
  }
  std::array<std::uint8_t, kRecordPrefixBytes> prefix{};
  if (auto st = readAt(unit.offset, prefix); !st) return st.error().within(at(unit));
  if (prefix[0] != static_cast<std::uint8_t>(Opcode::chunk) || little(&prefix[1], 8) != content_length)
    return Error::inputDamaged(fmt::format("{}: no Chunk record of {} bytes there (opcode {:#04x}, {} bytes)",
                                           at(unit), content_length, prefix[0], little(&prefix[1], 8)));
  std::vector<std::uint8_t> head(std::min<std::uint64_t>(content_length, kChunkHeaderMaxBytes));
  if (auto st = readAt(unit.offset + kRecordPrefixBytes, head); !st) return st.error().within(at(unit));
  auto h = parseChunkHeader(head, content_length);
  if (!h) return h.error().within(at(unit));
  if (!isKnownCompression(h->compression))
    return Error::inputDamaged(
        fmt::format("{}: compression '{}' is none of zstd, lz4 and none", at(unit), h->compression));
  if (h->records_size > kMaxRecordBytes || h->uncompressed_size > kMaxRecordBytes)
    return Error::inputDamaged(
        fmt::format("{}: records of {} bytes, {} uncompressed: more than the {} allowed", at(unit),
                    h->records_size, h->uncompressed_size, kMaxRecordBytes));
  std::vector<std::uint8_t> stored(h->records_size);
  if (auto st = readAt(unit.offset + kRecordPrefixBytes + h->records_offset, stored); !st)
    return st.error().within(at(unit));
  auto records = decompressRecords(h->compression, stored, h->uncompressed_size);
  if (!records) return records.error().within(at(unit));
  if (h->uncompressed_crc != 0) {
    const std::uint32_t crc = crc32(*records);
    if (crc != h->uncompressed_crc)
      return Error::inputDamaged(fmt::format("{}: CRC-32 of its records {:08x}, the chunk says {:08x}",
                                             at(unit), crc, h->uncompressed_crc));
  }
  return records;
}

Status McapReader::forEachMessage(const std::set<std::uint16_t>& channel_ids, const Visit& visit,
                                  const Damage& damage) const {
  std::uint64_t wanted = 0;
  for (const std::uint16_t id : channel_ids) wanted |= channelBit(id);
  const auto report = [&](const std::string& what) {
    if (damage) damage(what);
  };
  for (const std::string& d : damage_) report(d);

  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < units_.size(); ++i)
    if ((units_[i].channel_mask & wanted) != 0) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return units_[a].start != units_[b].start ? units_[a].start < units_[b].start
                                              : units_[a].offset < units_[b].offset;
  });

  // The held units, the one whose next message comes first on top: by log time, then file order.
  const auto later = [](const HeldUnit* a, const HeldUnit* b) {
    const HeldEntry& x = a->entries[a->next];
    const HeldEntry& y = b->entries[b->next];
    if (x.log_time != y.log_time) return x.log_time > y.log_time;
    if (a->offset != b->offset) return a->offset > b->offset;
    return x.content > y.content;
  };
  std::priority_queue<HeldUnit*, std::vector<HeldUnit*>, decltype(later)> heap(later);
  std::map<const HeldUnit*, std::unique_ptr<HeldUnit>> held;
  std::uint64_t held_bytes = 0;
  bool told_overlap = false;

  const auto emitNext = [&] {
    HeldUnit* u = heap.top();
    heap.pop();
    const HeldEntry& e = u->entries[u->next++];
    const auto content = std::span<const std::uint8_t>(u->bytes).subspan(e.content, e.size);
    std::span<const std::uint8_t> data;
    const auto m = parseMessage(content, &data);
    MessageView v;
    v.channel = &channels_[channel_index_.at(m->channel_id)];
    v.sequence = m->sequence;
    v.log_time = m->log_time;
    v.publish_time = m->publish_time;
    v.chunk_offset = u->chunk ? u->offset : 0;
    v.record_offset = u->chunk ? e.content - kRecordPrefixBytes : u->offset;
    v.data = data;
    visit(v);
    if (u->next < u->entries.size()) {
      heap.push(u);
    } else {
      held_bytes -= u->bytes.size();
      held.erase(u);
    }
  };

  for (const std::size_t i : order) {
    const Unit& unit = units_[i];
    while (!heap.empty() && heap.top()->entries[heap.top()->next].log_time < unit.start) emitNext();
    if (!unit.damaged.empty()) {
      report(unit.damaged + "; its messages are skipped");
      continue;
    }
    while (!heap.empty() && held_bytes + unit.length > kMaxHeldBytes) {
      if (!told_overlap) {
        report(fmt::format(
            "{}: chunks overlap in time by more than {} MiB: some messages come out of time order",
            path_.string(), kMaxHeldBytes >> 20));
        told_overlap = true;
      }
      emitNext();
    }
    auto bytes = readUnit(unit);
    if (!bytes) {
      if (bytes.error().kind == ErrorKind::io) return bytes.error();
      report(bytes.error().message + "; its messages are skipped");
      continue;
    }
    auto h = std::make_unique<HeldUnit>();
    h->offset = unit.offset;
    h->chunk = unit.chunk;
    h->bytes = std::move(*bytes);
    const auto take = [&](std::span<const std::uint8_t> content, std::size_t at) -> Status {
      auto m = parseMessage(content, nullptr);
      if (!m) return m.error();
      if (!channel_ids.contains(m->channel_id)) return okStatus();
      if (!channel_index_.contains(m->channel_id))
        return Error::inputDamaged(
            fmt::format("a message on channel {}, which no Channel record defines", m->channel_id));
      h->entries.push_back({m->log_time, at, content.size()});
      return okStatus();
    };
    if (unit.chunk) {
      auto st = forEachRecord(
          h->bytes, [&](std::uint8_t op, std::span<const std::uint8_t> content, std::size_t pos) -> Status {
            if (static_cast<Opcode>(op) != Opcode::message) return okStatus();
            return take(content, pos + kRecordPrefixBytes);
          });
      if (!st)
        report(fmt::format(
            "{}: {} in its records; the {} messages before it are read, the rest of the chunk is skipped",
            at(unit), st.error().message, h->entries.size()));
    } else if (auto st = take(h->bytes, 0); !st) {
      report(fmt::format("{}: {}; skipped", at(unit), st.error().message));
    }
    if (h->entries.empty()) continue;
    std::stable_sort(h->entries.begin(), h->entries.end(),
                     [](const HeldEntry& a, const HeldEntry& b) { return a.log_time < b.log_time; });
    held_bytes += h->bytes.size();
    heap.push(h.get());
    held.emplace(h.get(), std::move(h));
  }
  while (!heap.empty()) emitNext();
  return okStatus();
}

}  // namespace ogf::mcap
