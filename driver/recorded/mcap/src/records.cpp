#include "ogf/mcap/records.hpp"

#include <fmt/format.h>

namespace ogf::mcap {

bool ByteReader::need(std::size_t n, const char* what) {
  if (!error_.empty()) return false;
  if (n > remaining()) {
    error_ =
        fmt::format("{} at byte {} of the record needs {} bytes, {} are left", what, pos_, n, remaining());
    return false;
  }
  return true;
}

std::uint64_t ByteReader::little(std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{bytes_[pos_ + i]} << (8 * i);
  pos_ += n;
  return v;
}

std::uint8_t ByteReader::u8(const char* what) {
  return need(1, what) ? static_cast<std::uint8_t>(little(1)) : 0;
}
std::uint16_t ByteReader::u16(const char* what) {
  return need(2, what) ? static_cast<std::uint16_t>(little(2)) : 0;
}
std::uint32_t ByteReader::u32(const char* what) {
  return need(4, what) ? static_cast<std::uint32_t>(little(4)) : 0;
}
std::uint64_t ByteReader::u64(const char* what) { return need(8, what) ? little(8) : 0; }

std::span<const std::uint8_t> ByteReader::take(std::size_t n, const char* what) {
  if (!need(n, what)) return {};
  const auto out = bytes_.subspan(pos_, n);
  pos_ += n;
  return out;
}

std::span<const std::uint8_t> ByteReader::prefixedBytes(const char* what) {
  const std::uint32_t n = u32(what);
  return take(n, what);
}

std::string ByteReader::string(const char* what, std::size_t max_bytes) {
  const std::size_t at = pos_;
  const std::uint32_t n = u32(what);
  if (!ok()) return {};
  if (n > max_bytes) {
    error_ = fmt::format("{} at byte {} of the record claims {} bytes, more than the {} allowed", what, at, n,
                         max_bytes);
    return {};
  }
  const auto bytes = take(n, what);
  return {bytes.begin(), bytes.end()};
}

namespace {

template <class T>
Result<T> checked(const ByteReader& in, const char* record, T value) {
  if (!in.ok()) return Error::inputDamaged(fmt::format("{} record: {}", record, in.error()));
  return value;
}

}  // namespace

Result<Header> parseHeader(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  Header h;
  h.profile = in.string("profile");
  h.library = in.string("library");
  return checked(in, "Header", std::move(h));
}

Result<Footer> parseFooter(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  Footer f;
  f.summary_start = in.u64("summary_start");
  f.summary_offset_start = in.u64("summary_offset_start");
  f.summary_crc = in.u32("summary_crc");
  return checked(in, "Footer", f);
}

Result<Schema> parseSchema(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  Schema s;
  s.id = in.u16("id");
  s.name = in.string("name");
  s.encoding = in.string("encoding");
  in.prefixedBytes("data");
  return checked(in, "Schema", std::move(s));
}

Result<Channel> parseChannel(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  Channel c;
  c.id = in.u16("id");
  c.schema_id = in.u16("schema_id");
  c.topic = in.string("topic");
  c.message_encoding = in.string("message_encoding");
  in.prefixedBytes("metadata");  // Map<string, string>: its byte length must fit; ogf reads no key
  return checked(in, "Channel", std::move(c));
}

Result<MessageHeader> parseMessage(std::span<const std::uint8_t> content,
                                   std::span<const std::uint8_t>* data) {
  ByteReader in(content);
  MessageHeader m;
  m.channel_id = in.u16("channel_id");
  m.sequence = in.u32("sequence");
  m.log_time = in.u64("log_time");
  m.publish_time = in.u64("publish_time");
  if (data != nullptr && in.ok()) *data = content.subspan(kMessageHeaderBytes);
  return checked(in, "Message", m);
}

Result<ChunkHeader> parseChunkHeader(std::span<const std::uint8_t> content, std::uint64_t content_length) {
  ByteReader in(content);
  ChunkHeader c;
  c.message_start_time = in.u64("message_start_time");
  c.message_end_time = in.u64("message_end_time");
  c.uncompressed_size = in.u64("uncompressed_size");
  c.uncompressed_crc = in.u32("uncompressed_crc");
  c.compression = in.string("compression", 64);
  c.records_size = in.u64("records length");
  c.records_offset = in.offset();
  if (in.ok() && c.records_size != content_length - c.records_offset)
    return Error::inputDamaged(fmt::format("Chunk record: its records claim {} bytes, the record holds {}",
                                           c.records_size, content_length - c.records_offset));
  return checked(in, "Chunk", std::move(c));
}

Result<ChunkIndex> parseChunkIndex(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  ChunkIndex c;
  c.message_start_time = in.u64("message_start_time");
  c.message_end_time = in.u64("message_end_time");
  c.chunk_start_offset = in.u64("chunk_start_offset");
  c.chunk_length = in.u64("chunk_length");
  const auto offsets = in.prefixedBytes("message_index_offsets");
  in.u64("message_index_length");
  in.string("compression", 64);
  in.u64("compressed_size");
  in.u64("uncompressed_size");
  if (in.ok()) {
    // Map<uint16, uint64>: 10 bytes an entry, so the channels kept are bounded by the record's length.
    if (offsets.size() % 10 != 0)
      return Error::inputDamaged(
          fmt::format("Chunk Index record: message_index_offsets of {} bytes is no whole number of entries",
                      offsets.size()));
    ByteReader map(offsets);
    c.channel_ids.reserve(offsets.size() / 10);
    while (map.remaining() > 0) {
      c.channel_ids.push_back(map.u16("channel id"));
      map.u64("offset");
    }
  }
  return checked(in, "Chunk Index", std::move(c));
}

Result<Statistics> parseStatistics(std::span<const std::uint8_t> content) {
  ByteReader in(content);
  Statistics s;
  s.message_count = in.u64("message_count");
  in.u16("schema_count");
  in.u32("channel_count");
  in.u32("attachment_count");
  in.u32("metadata_count");
  s.chunk_count = in.u32("chunk_count");
  in.u64("message_start_time");
  in.u64("message_end_time");
  const auto counts = in.prefixedBytes("channel_message_counts");
  if (in.ok()) {
    if (counts.size() % 10 != 0)
      return Error::inputDamaged(
          fmt::format("Statistics record: channel_message_counts of {} bytes is no whole number of entries",
                      counts.size()));
    ByteReader map(counts);
    s.channel_message_counts.reserve(counts.size() / 10);
    while (map.remaining() > 0) {
      const std::uint16_t id = map.u16("channel id");
      s.channel_message_counts.emplace_back(id, map.u64("count"));
    }
  }
  return checked(in, "Statistics", std::move(s));
}

}  // namespace ogf::mcap
