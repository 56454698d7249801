#include "ogf/map_io/map_request.hpp"

#include <filesystem>
#include <utility>

namespace ogf::map_io {

Status checkMappingRequest(const MapRequest& r) {
  if (r.pcap.empty() && r.lcm_log.empty() && r.pcd.empty() && r.rosbag2.empty())
    return Error{"no input: give --pcap, --lcm-log, --rosbag2, --pcd or --from-map"};
  if (r.given.calib && r.pcap.empty() && r.lcm_log.empty() && r.rosbag2.empty())
    return Error{"--calib applies to raw packets: --pcap, --rosbag2 or an --lcm-log of packets"};
  if (!r.given.out) return Error{"--out is required when mapping"};
  return okStatus();
}

Status checkInputFilesExist(const MapRequest& r) {
  for (const auto& [flag, path] : {std::pair<const char*, const std::string&>{"--pcap", r.pcap},
                                   {"--lcm-log", r.lcm_log},
                                   {"--odometry", r.odometry}}) {
    if (!path.empty() && !std::filesystem::is_regular_file(path))
      return Error{std::string(flag) + ": " + path + ": no such file"};
  }
  return okStatus();
}

}  // namespace ogf::map_io
