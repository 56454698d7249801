#include "ogf/map_io/pose_message.hpp"

#include <bot_core/pose_t.hpp>
#include <ogf/odometry_t.hpp>

#include <fmt/format.h>

namespace ogf::map_io {
namespace {

std::int64_t fingerprintOf(std::span<const std::uint8_t> bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < 8; ++i) v = (v << 8) | bytes[i];
  return static_cast<std::int64_t>(v);
}

template <class Message>
Result<Message> decodeAs(std::span<const std::uint8_t> bytes, const char* type_name) {
  Message m;
  if (m.decode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0)
    return Error{fmt::format("{} of {} bytes does not decode", type_name, bytes.size())};
  return m;
}

}  // namespace

Result<fusion::Pose> decodePoseMessage(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 8) return Error{fmt::format("message of {} bytes has no fingerprint", bytes.size())};
  const std::int64_t fp = fingerprintOf(bytes);
  fusion::Pose pose;
  if (fp == ogf::odometry_t::getHash()) {
    auto m = decodeAs<ogf::odometry_t>(bytes, "ogf.odometry_t");
    if (!m) return m.error();
    pose.utime = m->utime;
    pose.position = {m->position[0], m->position[1], m->position[2]};
    pose.orientation = Eigen::Quaterniond(m->orientation[0], m->orientation[1], m->orientation[2], m->orientation[3]);
    return pose;
  }
  if (fp == bot_core::pose_t::getHash()) {
    auto m = decodeAs<bot_core::pose_t>(bytes, "bot_core.pose_t");
    if (!m) return m.error();
    pose.utime = m->utime;
    pose.position = {m->pos[0], m->pos[1], m->pos[2]};
    pose.orientation = Eigen::Quaterniond(m->orientation[0], m->orientation[1], m->orientation[2], m->orientation[3]);
    return pose;
  }
  return Error{fmt::format("fingerprint {:#018x} is neither ogf.odometry_t nor bot_core.pose_t",
                           static_cast<std::uint64_t>(fp))};
}

}  // namespace ogf::map_io
