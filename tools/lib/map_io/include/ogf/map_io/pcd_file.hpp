// Point clouds in PCL's PCD format (v0.7; DATA ascii or binary) as ogf-map's --pcd input. In PCL's
// convention the points and the VIEWPOINT are in the same frame, and VIEWPOINT's translation is where the
// rays start: each point is the end of a ray from there. Only the x, y and z fields are read (F 4 or F 8);
// other fields are stepped over. Points with a NaN or infinite coordinate (the holes of an organised
// cloud) are dropped and counted. binary_compressed is refused with a message saying so.
#pragma once

#include <ogf/common/result.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace ogf::map_io {

struct PcdCloud {
  std::vector<Eigen::Vector3d> points;  // the cloud's frame
  Eigen::Vector3d viewpoint_translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond viewpoint_rotation = Eigen::Quaterniond::Identity();  // read, not needed for rays
  std::int64_t non_finite = 0;  // points dropped
};

// `source` names the bytes in errors ("scan.pcd: header line 3: ...").
Result<PcdCloud> parsePcd(std::string_view bytes, std::string_view source);
Result<PcdCloud> readPcdFile(const std::filesystem::path& path);

}  // namespace ogf::map_io
