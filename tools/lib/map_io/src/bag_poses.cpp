#include "ogf/map_io/bag_poses.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

#include "ogf/rosbag/ros_messages.hpp"

namespace ogf::map_io {

using namespace ogf::rosbag;  // NOLINT(google-build-using-namespace): the bag's message types

namespace {

constexpr std::size_t kMaxPoseProblems = 20;

std::string_view withoutSlash(std::string_view frame) {
  return frame.starts_with('/') ? frame.substr(1) : frame;
}

fusion::Pose poseOf(const RosTime& stamp, const RosVector3& p, const RosQuaternion& q) {
  fusion::Pose pose;
  pose.utime = stamp.utime();
  pose.position = Eigen::Vector3d(p.x, p.y, p.z);
  pose.orientation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  return pose;
}

}  // namespace

Result<std::optional<BagPoseSource>> choosePoseSource(const rosbag::Rosbag2Storage& bag,
                                                      const std::string& topic,
                                                      const std::string& body_frame) {
  const std::string& where = bag.path().string();
  if (!topic.empty()) {
    const BagTopic* t = bag.topic(topic);
    if (t == nullptr) return Error{fmt::format("{}: no topic {}", where, topic)};
    if (t->type != kOdometryType && t->type != kTfMessageType)
      return Error{fmt::format("{}: topic {} is {}, not {} or {}", where, topic, t->type, kOdometryType,
                               kTfMessageType)};
    return std::optional<BagPoseSource>(BagPoseSource{topic, t->type, body_frame});
  }
  const auto odometry = bag.topicsOfType(kOdometryType);
  if (odometry.size() > 1) {
    std::string names;
    for (const BagTopic* t : odometry) names += (names.empty() ? "" : ", ") + t->name;
    return Error{fmt::format("{}: {} topics of type {} ({}): choose one", where, odometry.size(),
                             kOdometryType, names)};
  }
  if (odometry.size() == 1)
    return std::optional<BagPoseSource>(
        BagPoseSource{odometry.front()->name, std::string(kOdometryType), body_frame});
  if (const BagTopic* tf = bag.topic("/tf"); tf != nullptr && tf->type == kTfMessageType)
    return std::optional<BagPoseSource>(BagPoseSource{tf->name, tf->type, body_frame});
  return std::optional<BagPoseSource>();
}

Result<BagPoses> readBagPoses(const rosbag::Rosbag2Storage& bag, const BagPoseSource& source) {
  const BagTopic* t = bag.topic(source.topic);
  if (t == nullptr) return Error{fmt::format("{}: no topic {}", bag.path().string(), source.topic)};
  if (t->serialization_format != "cdr")
    return Error{fmt::format("{}: topic {} is serialized as '{}', not cdr", bag.path().string(), source.topic,
                             t->serialization_format)};
  const bool is_tf = t->type == kTfMessageType;
  BagPoses out;
  out.child_frame = is_tf ? std::string(withoutSlash(source.body_frame)) : std::string();
  const auto skip = [&](const BagMessage& m, const std::string& why) {
    ++out.skipped;
    if (out.problems.size() < kMaxPoseProblems)
      out.problems.push_back(
          fmt::format("{}: {} on {}: {}; skipped", m.file->string(), m.where(), source.topic, why));
  };
  auto st = bag.forEachMessage(
      {source.topic},
      [&](const BagMessage& m) {
        ++out.messages;
        if (!is_tf) {
          auto odo = decodeOdometry(m.data);
          if (!odo) return skip(m, odo.error().message);
          if (out.poses.empty()) {
            out.parent_frame = odo->header.frame_id;
            out.child_frame = odo->child_frame_id;
          }
          out.poses.push_back(poseOf(odo->header.stamp, odo->position, odo->orientation));
          return;
        }
        auto tf = decodeTfMessage(m.data);
        if (!tf) return skip(m, tf.error().message);
        for (const TransformStampedMessage& x : tf->transforms) {
          if (withoutSlash(x.child_frame_id) != out.child_frame) continue;
          if (out.parent_frame.empty()) out.parent_frame = x.header.frame_id;
          if (withoutSlash(x.header.frame_id) != withoutSlash(out.parent_frame)) {
            skip(m, fmt::format("{} from {}, not from {}", out.child_frame, x.header.frame_id,
                                out.parent_frame));
            continue;
          }
          out.poses.push_back(poseOf(x.header.stamp, x.translation, x.rotation));
        }
      },
      [&](const std::string& damage) {
        ++out.skipped;
        if (out.problems.size() < kMaxPoseProblems) out.problems.push_back(damage);
      });
  if (!st) return st.error();
  std::stable_sort(out.poses.begin(), out.poses.end(),
                   [](const fusion::Pose& a, const fusion::Pose& b) { return a.utime < b.utime; });
  return out;
}

}  // namespace ogf::map_io
