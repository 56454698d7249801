// What the ogf-map command line asks for: one input (a capture, an LCM log, a ROS 2 bag or PCD files, or a
// map made before), the settings that override the --config file, and the outputs. A setting's flag that
// was not given leaves the file's value (`given`); without --config the flags' defaults apply.
#pragma once

#include <cstddef>
#include <ogf/common/result.hpp>
#include <string>
#include <vector>

#include "ogf/map_io/map_exports.hpp"

namespace ogf::map_io {

struct MapRequest {
  // The input.
  std::string pcap, lcm_log, rosbag2, from_map;
  std::vector<std::string> pcd;
  std::string calib, odometry;
  bool is_static = false;
  std::string packets_topic, pose_topic, body_frame = "base_link";
  std::string scan_channel = "VELODYNE_SCAN", pose_channel = "POSE", packets_channel = "VELODYNE_PACKETS";

  // The settings.
  std::string config_path;
  double resolution = 0.2, max_range = 30.0, min_range = 0.4;
  int threads = 1;
  std::string time_base = "auto";  // auto | device | host
  std::string pose_correction = "none";
  std::size_t particles = 30;
  std::string page_dir;
  double page_out_distance = 60.0;

  // Which flags the command line gave.
  struct Given {
    bool calib = false, out = false, odometry = false, pose_topic = false;
    bool resolution = false, max_range = false, min_range = false, threads = false;
    bool time_base = false, pose_correction = false, particles = false;
  } given;

  // The outputs.
  std::string out, corrected_out;
  MapExports exports;
  double report_every = 0.0;  // seconds of scan time per --report-every row; 0: no report
};

// That mapping has an input and a map file to write, and that --calib goes with raw packets; the error
// says what to give.
Status checkMappingRequest(const MapRequest& request);

// That the input files named by --pcap, --lcm-log and --odometry exist; the error names the flag and the
// path ("--pcap: x.pcap: no such file").
Status checkInputFilesExist(const MapRequest& request);

}  // namespace ogf::map_io
