// A ROS 2 bag opened for reading, in rosbag2's sqlite3 storage or its MCAP storage (the default since Iron):
// the folder's metadata.yaml names the files in order (relative_file_paths); without it every *.db3 and
// *.mcap file in the folder is read, in name order. A path to one .db3 or .mcap file is read alone (which
// storage a file is comes from its first bytes, not its name). A folder with neither, holding exactly one
// subfolder that has either (the folder above a bag, e.g. where `ros2 bag record` made its time-named
// folder), opens that bag; with several such subfolders the error lists them. A sqlite3 file holds the
// tables `topics` (id, name, type, serialization_format, ...) and `messages` (id, topic_id, timestamp,
// data); an MCAP file one channel per topic whose schema names the type (ogf::mcap reads it, damage and
// all). Topics are merged across files by name. Messages come out file by file, each file's in timestamp
// order. Bags compressed by rosbag2 and other storage plugins are refused with their name. Errors name the
// file and what is wrong with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <ogf/common/result.hpp>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ogf::mcap {
class McapReader;
}

namespace ogf::rosbag {

struct BagTopic {
  std::string name;
  std::string type;                  // e.g. velodyne_msgs/msg/VelodyneScan
  std::string serialization_format;  // cdr
  std::int64_t message_count = 0;    // counted in the files, not taken from metadata.yaml
};

struct BagMessage {
  const BagTopic* topic = nullptr;
  const std::filesystem::path* file = nullptr;
  std::int64_t id = 0;                 // row id in its sqlite3 file
  std::int64_t timestamp_ns = 0;       // when the recorder received it
  std::span<const std::uint8_t> data;  // the serialized message; valid during the visit only
  // In an MCAP file: the chunk's offset in the file (0: a message outside chunks) and the message record's
  // offset (in the chunk's uncompressed records, else in the file).
  bool in_mcap = false;
  std::uint64_t chunk_offset = 0;
  std::uint64_t record_offset = 0;

  // Where in its file it is, for messages about it: "message 12" (the sqlite3 row), "the message at byte
  // 5130 of the chunk at byte 4096" (MCAP).
  std::string where() const;
};

class Rosbag2Storage {
 public:
  static Result<Rosbag2Storage> open(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }  // the bag's folder or file
  // The folder open() was given when the bag is its only bag subfolder; empty when open() was given the bag.
  const std::filesystem::path& searchedFolder() const { return searched_folder_; }
  // For the log when searchedFolder() is set ("A holds no bag itself; reading the bag in its subfolder
  // A/B"), else empty.
  std::string whereFound() const;
  const std::vector<std::filesystem::path>& files() const { return files_; }
  const std::vector<BagTopic>& topics() const { return topics_; }
  const BagTopic* topic(std::string_view name) const;
  std::vector<const BagTopic*> topicsOfType(std::string_view type) const;

  // Visits the messages of the named topics, in order. Damage an MCAP file's reader skips (a chunk that
  // fails its CRC or does not decompress, a file cut short) goes to `damaged`, each once per bag however
  // often the messages are read. Fails at the first file that cannot be read, after visiting what came
  // before it.
  Status forEachMessage(const std::vector<std::string>& topic_names,
                        const std::function<void(const BagMessage&)>& visit,
                        const std::function<void(const std::string&)>& damaged = {}) const;

 private:
  std::filesystem::path path_;
  std::filesystem::path searched_folder_;
  std::vector<std::filesystem::path> files_;
  // Per file: its MCAP reader, or null for a sqlite3 file.
  std::vector<std::shared_ptr<const mcap::McapReader>> mcap_files_;
  std::vector<BagTopic> topics_;
  // Per file: (topic id in that file, or its MCAP channel id; index into topics_).
  std::vector<std::vector<std::pair<std::int64_t, std::size_t>>> file_topics_;
  // Damage already reported by forEachMessage.
  std::shared_ptr<std::set<std::string>> reported_ = std::make_shared<std::set<std::string>>();

  Status addTopic(BagTopic t, std::int64_t id, const std::filesystem::path& file);
  Status openSqlite(const std::filesystem::path& file);
  Status openMcap(const std::filesystem::path& file);
};

}  // namespace ogf::rosbag
