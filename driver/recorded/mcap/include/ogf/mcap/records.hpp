// The records of an MCAP file (MCAP format specification, major version 0: "Records" and "Serialization"),
// parsed from their content bytes with every length checked against what is there. A record is
// <opcode uint8><content length uint64><content>; integers are little endian; a String is a uint32 byte
// length and the bytes; a Map or Array a uint32 byte length and its entries. Only the fields ogf uses are
// kept. Parsing never allocates more than the strings it returns, each at most kMaxNameBytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ogf/common/result.hpp>
#include <span>
#include <string>
#include <vector>

namespace ogf::mcap {

// 0x89 "MCAP" '0' "\r\n": the first and the last 8 bytes of a file ("Magic").
inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

// The opcodes of the specification's records (0x01-0x7F are reserved to it, 0x80-0xFF private).
enum class Opcode : std::uint8_t {
  header = 0x01,
  footer = 0x02,
  schema = 0x03,
  channel = 0x04,
  message = 0x05,
  chunk = 0x06,
  message_index = 0x07,
  chunk_index = 0x08,
  attachment = 0x09,
  attachment_index = 0x0A,
  statistics = 0x0B,
  metadata = 0x0C,
  metadata_index = 0x0D,
  summary_offset = 0x0E,
  data_end = 0x0F,
};

inline constexpr std::size_t kRecordPrefixBytes = 9;    // opcode + content length
inline constexpr std::size_t kFooterContentBytes = 20;  // two uint64 and a uint32
inline constexpr std::size_t kFooterRecordBytes = kRecordPrefixBytes + kFooterContentBytes;
inline constexpr std::size_t kMessageHeaderBytes = 2 + 4 + 8 + 8;  // before a message's data
// Topic, schema and encoding names longer than this are refused: no ROS name comes near it, and it bounds
// what one record can make a reader keep.
inline constexpr std::size_t kMaxNameBytes = 4096;

struct Header {
  std::string profile;  // "ros2" for ROS 2 bags
  std::string library;
};

struct Footer {
  std::uint64_t summary_start = 0;  // 0: no summary section
  std::uint64_t summary_offset_start = 0;
  std::uint32_t summary_crc = 0;  // CRC-32 of the summary up to this field; 0: not given
};

struct Schema {
  std::uint16_t id = 0;
  std::string name;      // e.g. velodyne_msgs/msg/VelodyneScan, foxglove.PointCloud
  std::string encoding;  // ros2msg, ros2idl, protobuf, jsonschema, ...
};

struct Channel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // cdr, protobuf, json, ...
};

struct MessageHeader {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;  // nanoseconds; for a ROS 2 bag the recorder's receive time
  std::uint64_t publish_time = 0;
};

// A Chunk's fields before its records, and where the records lie in the record's content.
struct ChunkHeader {
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;  // 0: not given
  std::string compression;             // "", "zstd" or "lz4"
  std::uint64_t records_offset = 0;    // from the start of the content
  std::uint64_t records_size = 0;
};

struct ChunkIndex {
  std::uint64_t message_start_time = 0;
  std::uint64_t message_end_time = 0;
  std::uint64_t chunk_start_offset = 0;
  std::uint64_t chunk_length = 0;          // the whole record, prefix included
  std::vector<std::uint16_t> channel_ids;  // with a message index; empty: not indexed by channel
};

struct Statistics {
  std::uint64_t message_count = 0;
  std::uint32_t chunk_count = 0;
  std::vector<std::pair<std::uint16_t, std::uint64_t>> channel_message_counts;
};

// Each parser takes a record's content (after the 9-byte prefix). Errors say which field does not fit.
Result<Header> parseHeader(std::span<const std::uint8_t> content);
Result<Footer> parseFooter(std::span<const std::uint8_t> content);
Result<Schema> parseSchema(std::span<const std::uint8_t> content);
Result<Channel> parseChannel(std::span<const std::uint8_t> content);
// `data` receives the message's bytes (inside `content`).
Result<MessageHeader> parseMessage(std::span<const std::uint8_t> content,
                                   std::span<const std::uint8_t>* data);
// `content` needs to hold only the fields before the records; `content_length` is the whole content's, which
// the records' length must fill exactly.
Result<ChunkHeader> parseChunkHeader(std::span<const std::uint8_t> content, std::uint64_t content_length);
Result<ChunkIndex> parseChunkIndex(std::span<const std::uint8_t> content);
Result<Statistics> parseStatistics(std::span<const std::uint8_t> content);

// Little-endian reads of a byte range; every read checks that the bytes are there and, once one fails,
// every later one fails too, so a parser reads a whole record and checks once.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t u8(const char* what);
  std::uint16_t u16(const char* what);
  std::uint32_t u32(const char* what);
  std::uint64_t u64(const char* what);
  // A String (uint32 length, then the bytes); refused beyond `max_bytes`.
  std::string string(const char* what, std::size_t max_bytes = kMaxNameBytes);
  // A uint32 byte length and that many bytes, viewed in place.
  std::span<const std::uint8_t> prefixedBytes(const char* what);
  std::span<const std::uint8_t> take(std::size_t n, const char* what);
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }

 private:
  bool need(std::size_t n, const char* what);
  std::uint64_t little(std::size_t n);
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
  std::string error_;
};

}  // namespace ogf::mcap
