// A ROS 2 bag in rosbag2's sqlite3 storage, opened for reading: the folder's metadata.yaml names the .db3
// files in order (relative_file_paths); without it every *.db3 in the folder is read, in name order. A
// path to one .db3 file is read alone. A folder with neither, holding exactly one subfolder that has either
// (the folder above a bag, e.g. where `ros2 bag record` made its time-named folder), opens that bag; with
// several such subfolders the error lists them. Each file holds the tables `topics` (id, name, type,
// serialization_format, ...) and `messages` (id, topic_id, timestamp, data); topics are merged across files
// by name. Messages come out file by file, each file's in timestamp order. Compressed bags and other
// storage plugins (mcap) are refused with their name. Errors name the file and what is wrong with it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ogf/common/result.hpp>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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
  std::int64_t id = 0;                 // row id in its file
  std::int64_t timestamp_ns = 0;       // when the recorder received it
  std::span<const std::uint8_t> data;  // the serialized message; valid during the visit only
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

  // Visits the messages of the named topics, in order. Fails at the first file that cannot be read, after
  // visiting what came before it.
  Status forEachMessage(const std::vector<std::string>& topic_names,
                        const std::function<void(const BagMessage&)>& visit) const;

 private:
  std::filesystem::path path_;
  std::filesystem::path searched_folder_;
  std::vector<std::filesystem::path> files_;
  std::vector<BagTopic> topics_;
  // Per file: (topic id in that file, index into topics_).
  std::vector<std::vector<std::pair<std::int64_t, std::size_t>>> file_topics_;
};

}  // namespace ogf::rosbag
