// The ROS 2 messages ogf reads from a bag, decoded from CDR with their published definitions:
//   velodyne_msgs/msg/VelodyneScan  std_msgs/Header header, VelodynePacket[] packets
//     VelodynePacket                builtin_interfaces/Time stamp, uint8[1206] data
//   nav_msgs/msg/Odometry           std_msgs/Header header, string child_frame_id,
//                                   geometry_msgs/PoseWithCovariance pose (Pose pose, float64[36]
//                                   covariance), geometry_msgs/TwistWithCovariance twist (Twist twist,
//                                   float64[36] covariance)
//   tf2_msgs/msg/TFMessage          geometry_msgs/TransformStamped[] transforms
//     TransformStamped              std_msgs/Header header, string child_frame_id,
//                                   Transform transform (Vector3 translation, Quaternion rotation)
// with std_msgs/Header = {Time stamp, string frame_id}, Time = {int32 sec, uint32 nanosec} and Point,
// Vector3 = {float64 x, y, z}, Quaternion = {float64 x, y, z, w}. Errors name the field and byte offset.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <ogf/common/result.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ogf/rosbag/rosbag2_storage.hpp"

namespace ogf::rosbag {

inline constexpr std::string_view kVelodyneScanType = "velodyne_msgs/msg/VelodyneScan";
inline constexpr std::string_view kOdometryType = "nav_msgs/msg/Odometry";
inline constexpr std::string_view kTfMessageType = "tf2_msgs/msg/TFMessage";
inline constexpr std::size_t kVelodynePacketBytes = 1206;  // VelodynePacket.data: one UDP payload

struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;

  std::int64_t nanoseconds() const { return std::int64_t{sec} * 1'000'000'000 + std::int64_t{nanosec}; }
  // Microseconds since the epoch, rounded to the nearest (a half rounds up), as a pcap written from the same
  // stamps holds them.
  std::int64_t utime() const;
};

struct RosHeader {
  RosTime stamp;
  std::string frame_id;
};

struct VelodynePacketView {
  RosTime stamp;
  std::span<const std::uint8_t> data;  // kVelodynePacketBytes, inside the decoded message's bytes
};

struct VelodyneScanMessage {
  RosHeader header;
  std::vector<VelodynePacketView> packets;
};

struct RosVector3 {
  double x = 0, y = 0, z = 0;
};

struct RosQuaternion {
  double x = 0, y = 0, z = 0, w = 1;
};

struct OdometryMessage {
  RosHeader header;
  std::string child_frame_id;
  RosVector3 position;
  RosQuaternion orientation;
  std::array<double, 36> pose_covariance{};
  RosVector3 linear_velocity, angular_velocity;
  std::array<double, 36> twist_covariance{};
};

struct TransformStampedMessage {
  RosHeader header;  // frame_id: the parent frame
  std::string child_frame_id;
  RosVector3 translation;
  RosQuaternion rotation;
};

struct TfMessage {
  std::vector<TransformStampedMessage> transforms;
};

// The packets view `message`, which must outlive the result.
Result<VelodyneScanMessage> decodeVelodyneScan(std::span<const std::uint8_t> message);
Result<OdometryMessage> decodeOdometry(std::span<const std::uint8_t> message);
Result<TfMessage> decodeTfMessage(std::span<const std::uint8_t> message);

// Whether this library decodes messages of `type`.
bool isDecodedType(std::string_view type);
// "/imu (sensor_msgs/msg/Imu, 100 messages), ..." for the topics whose type is not decoded; "" when none.
std::string undecodedTopicsSummary(std::span<const BagTopic> topics);

}  // namespace ogf::rosbag
