#include "ogf/rosbag/ros_messages.hpp"

#include <fmt/format.h>

#include "ogf/rosbag/cdr_reader.hpp"

namespace ogf::rosbag {
namespace {

// Smallest CDR sizes of sequence elements, to refuse lengths the bytes left cannot hold.
constexpr std::size_t kMinPacketBytes = 8 + kVelodynePacketBytes;  // Time + uint8[1206]
constexpr std::size_t kMinTransformBytes = 8 + 4 + 4 + 7 * 8;      // Time, two empty strings, 7 float64

void readTime(CdrReader& in, RosTime& t, const char* what) {
  in.i32(t.sec, what);
  in.u32(t.nanosec, what);
}

void readHeader(CdrReader& in, RosHeader& h) {
  readTime(in, h.stamp, "header.stamp");
  in.string(h.frame_id, "header.frame_id");
}

void readVector3(CdrReader& in, RosVector3& v, const char* what) {
  in.f64(v.x, what);
  in.f64(v.y, what);
  in.f64(v.z, what);
}

void readQuaternion(CdrReader& in, RosQuaternion& q, const char* what) {
  in.f64(q.x, what);
  in.f64(q.y, what);
  in.f64(q.z, what);
  in.f64(q.w, what);
}

// Opens `bytes` as CDR, lets `read` fill a Message from it, and reports the first failure as an error of
// `type`.
template <class Message, class Read>
Result<Message> decodeAs(std::span<const std::uint8_t> bytes, std::string_view type, Read read) {
  auto opened = CdrReader::open(bytes);
  if (!opened) return Error{fmt::format("{}: {}", type, opened.error().message)};
  Message message;
  read(*opened, message);
  if (!opened->ok()) return Error{fmt::format("{}: {}", type, opened->error())};
  return message;
}

}  // namespace

std::int64_t RosTime::utime() const {
  const std::int64_t ns = nanoseconds() + 500;
  // Floor division, so times before the epoch round the same way.
  return ns >= 0 ? ns / 1000 : -((-ns + 999) / 1000);
}

Result<VelodyneScanMessage> decodeVelodyneScan(std::span<const std::uint8_t> message) {
  return decodeAs<VelodyneScanMessage>(message, kVelodyneScanType,
                                       [](CdrReader& in, VelodyneScanMessage& scan) {
                                         readHeader(in, scan.header);
                                         std::uint32_t n = 0;
                                         if (!in.sequenceLength(n, kMinPacketBytes, "packets")) return;
                                         scan.packets.resize(n);
                                         for (VelodynePacketView& p : scan.packets) {
                                           readTime(in, p.stamp, "packets[].stamp");
                                           if (!in.octets(kVelodynePacketBytes, p.data, "packets[].data"))
                                             return;
                                         }
                                       });
}

Result<OdometryMessage> decodeOdometry(std::span<const std::uint8_t> message) {
  return decodeAs<OdometryMessage>(message, kOdometryType, [](CdrReader& in, OdometryMessage& odo) {
    readHeader(in, odo.header);
    in.string(odo.child_frame_id, "child_frame_id");
    readVector3(in, odo.position, "pose.pose.position");
    readQuaternion(in, odo.orientation, "pose.pose.orientation");
    in.f64s(odo.pose_covariance, "pose.covariance");
    readVector3(in, odo.linear_velocity, "twist.twist.linear");
    readVector3(in, odo.angular_velocity, "twist.twist.angular");
    in.f64s(odo.twist_covariance, "twist.covariance");
  });
}

Result<TfMessage> decodeTfMessage(std::span<const std::uint8_t> message) {
  return decodeAs<TfMessage>(message, kTfMessageType, [](CdrReader& in, TfMessage& tf) {
    std::uint32_t n = 0;
    if (!in.sequenceLength(n, kMinTransformBytes, "transforms")) return;
    tf.transforms.resize(n);
    for (TransformStampedMessage& t : tf.transforms) {
      readHeader(in, t.header);
      in.string(t.child_frame_id, "transforms[].child_frame_id");
      readVector3(in, t.translation, "transforms[].transform.translation");
      readQuaternion(in, t.rotation, "transforms[].transform.rotation");
      if (!in.ok()) return;
    }
  });
}

bool isDecodedType(std::string_view type) {
  return type == kVelodyneScanType || type == kOdometryType || type == kTfMessageType;
}

std::string undecodedTopicsSummary(std::span<const BagTopic> topics) {
  std::string out;
  for (const BagTopic& t : topics) {
    if (isDecodedType(t.type)) continue;
    if (!out.empty()) out += ", ";
    out += fmt::format("{} ({}, {} message{})", t.name, t.type, t.message_count,
                       t.message_count == 1 ? "" : "s");
  }
  return out;
}

}  // namespace ogf::rosbag
