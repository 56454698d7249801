// The odometry ogf-replay publishes beside a capture, as ready-to-publish LCM messages in time order:
// from a CSV file (`utime,x,y,z,qw,qx,qy,qz`, as ogf-sim writes it; each line becomes an ogf.odometry_t,
// frame "odom", child "base_link") or from an LCM log (every event on the pose channel, republished byte
// for byte, so bot_core.pose_t logs replay too; its utime is the event's log timestamp). The utime is on
// the capture's clock: the replay publishes each message when its clock reaches it.
#pragma once

#include <ogf/common/result.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace ogf::replay {

struct PoseEvent {
  std::int64_t utime = 0;           // µs since the epoch, capture clock
  std::vector<std::uint8_t> bytes;  // the encoded message
};

struct PoseEvents {
  std::vector<PoseEvent> events;  // sorted by utime (stable)
  std::int64_t skipped = 0;       // malformed lines, or log events on other channels are not counted
  std::vector<std::string> problems;  // the first 50 skipped lines, each naming file, line and field
};

// CSV or LCM log, told apart by the file's first bytes (an LCM log starts with the sync word 0xEDA1DA01).
// A malformed CSV line is skipped and described; a file that cannot be opened, or holds no event at all,
// is an error naming it.
Result<PoseEvents> loadPoseEvents(const std::filesystem::path& path, const std::string& lcm_channel);

// Parses pose CSV text (ogf/tools/pose_csv.hpp) into odometry_t events; `source` names it in problems
// ("odometry.csv:12: ...").
PoseEvents parsePoseCsv(const std::string& text, const std::string& source);

// The same pose message with its utime replaced by `restamp(utime)`, every other field as it was, for
// publishing recorded odometry on another clock (odometry_clock.hpp). Decodes ogf.odometry_t and
// bot_core.pose_t (told apart by fingerprint, the two types the mapper reads); an error for anything else.
Result<std::vector<std::uint8_t>> restampPose(const std::vector<std::uint8_t>& bytes,
                                              const std::function<std::int64_t(std::int64_t)>& restamp);

}  // namespace ogf::replay
