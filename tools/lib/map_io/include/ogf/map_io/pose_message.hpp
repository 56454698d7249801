// Decodes one POSE message into a fusion::Pose. The channel may carry ogf.odometry_t or libbot2's
// bot_core.pose_t; which one is told by the 8-byte fingerprint every LCM message starts with
// (getHash() of the type), never by guessing from the size.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/fusion/pose.hpp>

#include <cstdint>
#include <span>

namespace ogf::map_io {

// Error when the fingerprint is neither type's or the message does not decode.
Result<fusion::Pose> decodePoseMessage(std::span<const std::uint8_t> bytes);

}  // namespace ogf::map_io
