#include "ogf/map_io/pose_message.hpp"

#include "ogf/adapters/message_adapters.hpp"

namespace ogf::map_io {

// The daemon's decoder (mapper/adapters), so ogf-map and ogf-mapper read POSE identically.
Result<fusion::Pose> decodePoseMessage(std::span<const std::uint8_t> bytes) {
  return adapters::decodePose(bytes.data(), bytes.size());
}

}  // namespace ogf::map_io
