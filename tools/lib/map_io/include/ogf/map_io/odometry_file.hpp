// The robot's odometry for an offline run, read whole before the scans: a CSV file
// (`utime,x,y,z,qw,qx,qy,qz`, utime in microseconds on the capture's clock, an optional header line, '#'
// comments) or an LCM log whose POSE channel carries ogf.odometry_t or bot_core.pose_t. The kind is told by
// the file's first bytes, not its name. A malformed line or record is skipped and described (file and
// line, or file and event number), so one bad line does not throw away an hour of odometry; only a file
// that cannot be read at all is an error.
#pragma once

#include <ogf/common/result.hpp>
#include <ogf/fusion/pose.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ogf::map_io {

struct OdometryFile {
  std::vector<fusion::Pose> poses;    // in file order
  std::vector<std::string> problems;  // one message per skipped line or record, naming file and line
  std::int64_t skipped = 0;           // lines or records skipped (problems may be capped, this is not)
};

// Parses CSV text; `source` names it in messages ("odometry.csv:12: ...").
OdometryFile parseOdometryCsv(std::string_view text, std::string_view source);
Result<OdometryFile> readOdometryCsv(const std::filesystem::path& path);

// Whether the file starts with an LCM log event's sync word.
bool isLcmLog(const std::filesystem::path& path);

// The poses on `channel` of an LCM log, each decoded as odometry_t or bot_core.pose_t by its fingerprint.
Result<OdometryFile> readOdometryLcmLog(const std::filesystem::path& path, const std::string& channel = "POSE");

// Writes poses as the CSV the readers take (with its header line), e.g. the corrected trajectory of a
// pose-corrected run for ogf-eval --corrected.
Status writeOdometryCsv(const std::filesystem::path& path, const std::vector<fusion::Pose>& poses);

// CSV or LCM log, by content.
Result<OdometryFile> readOdometry(const std::filesystem::path& path, const std::string& lcm_channel = "POSE");

}  // namespace ogf::map_io
