// The robot body's poses recorded in a bag, as ogf-map's odometry: a nav_msgs/msg/Odometry topic (the pose
// of child_frame_id in header.frame_id) or the transforms of a tf2_msgs/msg/TFMessage topic whose
// child_frame_id is the body frame (base_link by default; a leading '/' is ignored), each at its
// header.stamp rounded to the microsecond, sorted by time. Which source, by default: the bag's only
// Odometry topic, else its /tf topic (never /tf_static, whose transforms are not motion). Messages that do
// not decode, and transforms to the body from a parent other than the first one seen, are skipped and
// described.
#pragma once

#include <cstdint>
#include <ogf/common/result.hpp>
#include <ogf/fusion/pose.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ogf/rosbag/rosbag2_storage.hpp"

namespace ogf::map_io {

struct BagPoseSource {
  std::string topic;
  std::string type;                      // kOdometryType or kTfMessageType
  std::string body_frame = "base_link";  // the TF child frame taken; unused for Odometry
};

struct BagPoses {
  std::vector<fusion::Pose> poses;    // sorted by utime
  std::string parent_frame;           // the frame the poses are in (odom, map, ...)
  std::string child_frame;            // the body frame
  std::int64_t messages = 0;          // messages read on the topic
  std::int64_t skipped = 0;           // messages or transforms left out, and damage the storage skipped
  std::vector<std::string> problems;  // the first few
};

// The pose source: `topic` when given (an Odometry or TFMessage topic of the bag), else the default above;
// nullopt when the bag has neither. An error asks for a choice (several Odometry topics) or names what
// is wrong with the requested topic.
Result<std::optional<BagPoseSource>> choosePoseSource(const rosbag::Rosbag2Storage& bag,
                                                      const std::string& topic,
                                                      const std::string& body_frame = "base_link");

Result<BagPoses> readBagPoses(const rosbag::Rosbag2Storage& bag, const BagPoseSource& source);

}  // namespace ogf::map_io
