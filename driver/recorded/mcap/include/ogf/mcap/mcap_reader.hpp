// An MCAP file opened for reading its messages (MCAP format specification; "Implementation Notes" for the
// summary). Opening reads the summary section when the file has a valid one (footer, summary CRC, the
// channels, a Chunk Index for every chunk and Statistics with per-channel counts: an indexed file), else
// walks the data section from the start, decompressing every chunk to learn its channels and count their
// messages. Either way the messages come out in log-time order (ties in file order), as a rosbag2 sqlite3
// bag gives them, from chunks compressed with zstd, lz4 or not at all, and from messages outside chunks.
//
// Damage never stops the rest from being read: a chunk whose records fail their CRC, do not decompress
// or do not parse is reported with its byte offset and skipped (the messages of its records before the
// damage are kept), and a file cut short is read up to the cut. What the file claims never sizes an
// allocation beyond a fixed bound: a record, a chunk's compressed and uncompressed records and the
// summary are each refused beyond kMaxRecordBytes; names beyond kMaxNameBytes; chunks in all beyond
// kMaxChunks; and chunks that overlap in time are held at once only up to kMaxHeldBytes (beyond, messages
// may come out of time order, and that is reported once).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <ogf/common/result.hpp>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "ogf/mcap/records.hpp"

namespace ogf::mcap {

inline constexpr std::uint64_t kMaxRecordBytes = std::uint64_t{256} << 20;
inline constexpr std::size_t kMaxChunks = std::size_t{1} << 22;
inline constexpr std::uint64_t kMaxHeldBytes = std::uint64_t{512} << 20;

struct ChannelInfo {
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;  // cdr for ROS 2
  std::string schema_name;       // the message type, e.g. velodyne_msgs/msg/VelodyneScan
  std::string schema_encoding;   // ros2msg, ros2idl, ...
  std::uint64_t message_count = 0;
};

struct MessageView {
  const ChannelInfo* channel = nullptr;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;
  std::uint64_t publish_time = 0;
  std::uint64_t chunk_offset = 0;  // the chunk's record in the file; 0 for a message outside chunks
  std::uint64_t record_offset =
      0;  // the message's record: in the chunk's uncompressed records, else the file
  std::span<const std::uint8_t> data;  // valid during the visit only
};

class McapReader {
 public:
  using Visit = std::function<void(const MessageView&)>;
  // Receives each piece of damage found while reading ("FILE: chunk at byte N: ...; its messages are
  // skipped"), once per call.
  using Damage = std::function<void(const std::string&)>;

  // Errors: the file cannot be read, is no MCAP file (magic, header), or is damaged before any message.
  static Result<McapReader> open(const std::filesystem::path& file);
  ~McapReader();
  McapReader(McapReader&&) noexcept;
  McapReader& operator=(McapReader&&) noexcept;

  const std::filesystem::path& path() const { return path_; }
  const std::string& profile() const { return profile_; }
  bool indexed() const { return indexed_; }  // read through the summary section
  const std::vector<ChannelInfo>& channels() const { return channels_; }
  // What opening found damaged (a cut, a chunk that does not check), in file order.
  const std::vector<std::string>& damage() const { return damage_; }

  // Visits the messages of the channels `channel_ids` in log-time order; damage is reported to `damage`
  // (chunks found damaged at open among them) and skipped. Fails only when the file cannot be read at all.
  Status forEachMessage(const std::set<std::uint16_t>& channel_ids, const Visit& visit,
                        const Damage& damage = {}) const;

 private:
  // What the messages are read from: a chunk, or one message record outside chunks.
  struct Unit {
    std::uint64_t offset = 0;  // of the record in the file
    std::uint64_t length = 0;  // of the whole record
    std::uint64_t start = 0;   // earliest and latest log time in it
    std::uint64_t end = 0;
    std::uint64_t channel_mask = ~std::uint64_t{0};  // bit (id % 64) of every channel it may hold
    bool chunk = true;
    std::string damaged;  // why it cannot be read, when opening found out
  };
  struct SchemaName {
    std::string name, encoding;
  };

  McapReader() = default;
  // True when the summary was read; false when the file has none that covers it (then scan()).
  Result<bool> readSummary(std::uint64_t file_size);
  void scan(std::uint64_t file_size);
  void scanChunk(Unit& unit);
  void addChannel(const Channel& c);
  void addSchema(const Schema& s);
  // The chunk's records, decompressed and checked; or the message record's content.
  Result<std::vector<std::uint8_t>> readUnit(const Unit& unit) const;
  Status readAt(std::uint64_t offset, std::span<std::uint8_t> out) const;
  std::string at(const Unit& unit) const;

  std::filesystem::path path_;
  int fd_ = -1;
  std::string profile_;
  bool indexed_ = false;
  std::vector<ChannelInfo> channels_;
  std::map<std::uint16_t, std::size_t> channel_index_;
  std::map<std::uint16_t, SchemaName> schemas_;
  std::vector<Unit> units_;
  std::vector<std::string> damage_;
  std::uint64_t names_bytes_ = 0;
};

}  // namespace ogf::mcap
