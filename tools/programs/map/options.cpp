// ogf-map's command line: the flags, their help and which ones exclude or need which (the program's
// description is the --help text). The values land in a map_io::MapRequest (ogf/map_io/map_request.hpp).
#include "options.hpp"

#include "ogf/common/command_line.hpp"

namespace ogf::map_program {
namespace {

const char* const kDescription =
    "Builds an Occupancy Grid Filter map offline, from one input:\n"
    "  --pcap FILE [--calib FILE] (--odometry FILE | --static)   a Velodyne capture\n"
    "  --lcm-log FILE                                             lidar_scan_t and poses as lcm-logger "
    "records them\n"
    "  --rosbag2 DIR                                              a ROS 2 bag (sqlite3 or MCAP): "
    "VelodyneScan "
    "packets,\n"
    "                                                             poses from its Odometry or /tf\n"
    "  --pcd FILE...                                              PCL point clouds (rays from each "
    "VIEWPOINT)\n"
    "or exports a map already made: --from-map FILE (a map file or a daemon snapshot) with any --export-*\n"
    "and --png; then --out is optional and the last line is  map <kind> cells <allocated cells>.\n"
    "With --pose-correction scan-match|rbpf the odometry's drift is corrected scan by scan before mapping.\n"
    "Odometry: CSV `utime,x,y,z,qw,qx,qy,qz` (utime in us on the clock --time names) or an LCM log with\n"
    "ogf.odometry_t or bot_core.pose_t on POSE. Scans the odometry does not cover are counted and left out,\n"
    "never extrapolated; when none is covered because the two are on different clocks, the log says which\n"
    "--time fixes it. --static (pose_source: static) holds the body at static_pose, the origin by default.\n"
    "--config reads ogf-mapper's configuration file (ogf-mapper --print-config lists its keys); flags "
    "override it.\n"
    "At the end one line on stdout:\n"
    "  scans <mapped> measurements <cell measurements> cells <allocated cells> seconds <wall time>\n"
    "Exit 0 when at least one scan was mapped and every output written, 1 when nothing could be mapped or\n"
    "an output failed, 2 on bad flags or configuration.";

// The map file and the settings that override the --config file.
void addMapOptions(CLI::App& app, map_io::MapRequest& r) {
  app.add_option("--out", r.out, "Map file to write (ogf map format, see ogf/filter/map_file.hpp)");
  app.add_option("--config", r.config_path,
                 "ogf-mapper's YAML configuration (map, filter, fusion, time_base, pose_source, static_pose, "
                 "pose_correction; its other keys are ignored here); flags override it")
      ->check(CLI::ExistingFile);
  app.add_option("--resolution", r.resolution, "Cell size, metres")
      ->capture_default_str()
      ->check(ogf::cli::positive());
  app.add_option("--max-range", r.max_range, "Rays are cut here (free cells only beyond), metres")
      ->capture_default_str()
      ->check(ogf::cli::positive());
  app.add_option("--min-range", r.min_range, "Returns closer than this are ignored, metres")
      ->capture_default_str()
      ->check(ogf::cli::nonNegative());
}

// The inputs: a capture with its odometry, an LCM log, a ROS 2 bag, PCD files, and their channels and topics.
void addInputOptions(CLI::App& app, map_io::MapRequest& r) {
  app.add_option("--pcap", r.pcap, "Velodyne capture (pcap or pcapng)");
  app.add_option("--calib", r.calib, "Calibration for --pcap or --rosbag2: VeloView XML or ROS YAML");
  app.add_option("--odometry", r.odometry, "Odometry: CSV or LCM log (POSE)");
  app.add_flag("--static", r.is_static,
               "The sensor does not move (a tripod): the body at the config's static_pose, by "
               "default the origin");
  app.add_option(
      "--lcm-log", r.lcm_log,
      "LCM log with scans (VELODYNE_SCAN, else the raw packets on VELODYNE_PACKETS) and poses (POSE)");
  app.add_option("--pcd", r.pcd, "PCD files, one scan each");
  auto* bag_opt =
      app.add_option("--rosbag2", r.rosbag2,
                     "ROS 2 bag folder (sqlite3 or MCAP), or one .db3 or .mcap file: "
                     "velodyne_msgs/msg/VelodyneScan packets, poses from "
                     "nav_msgs/msg/Odometry or tf2_msgs/msg/TFMessage; --time defaults to host (ROS stamps)");
  app.add_option("--packets-topic", r.packets_topic,
                 "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  app.add_option("--pose-topic", r.pose_topic,
                 "Odometry or TFMessage topic of --rosbag2 (default: the only Odometry topic, else /tf)")
      ->needs(bag_opt);
  app.add_option("--body-frame", r.body_frame, "The body's TF child frame when the poses come from /tf")
      ->capture_default_str()
      ->needs(bag_opt);
  app.add_option(
         "--time", r.time_base,
         "Clock the odometry is on: device (scan device time), host (receive time) or auto (device for "
         "scans whose device time is GPS/PPS-locked UTC, host otherwise; ogf-mapper's rule). Default: "
         "the config's time_base, else auto (host for --rosbag2)")
      ->check(CLI::IsMember({"auto", "device", "host"}))
      ->capture_default_str();
  app.add_option("--scan-channel", r.scan_channel, "Scan channel in --lcm-log")->capture_default_str();
  app.add_option("--packets-channel", r.packets_channel,
                 "Raw packet channel in --lcm-log, decoded when the log has no scans")
      ->capture_default_str();
  app.add_option("--pose-channel", r.pose_channel, "Pose channel in LCM logs")->capture_default_str();
}

void addExportOptions(CLI::App& app, map_io::MapRequest& r) {
  app.add_option("--export-csv", r.exports.csv,
                 "Every allocated cell: x,y,z,p,class,variance (cell centres, metres)");
  app.add_option("--export-ply", r.exports.ply, "Occupied cells as binary PLY (x, y, z, p, variance)");
  app.add_option("--export-pcd", r.exports.pcd, "Occupied cells as binary PCD v0.7 (x, y, z, p, variance)");
  app.add_option("--export-bt", r.exports.bt, "OctoMap binary tree (.bt) for octovis");
  auto* png_opt =
      app.add_option("--png", r.exports.png_dir, "Folder for top-down occupancy.png and entropy.png");
  app.add_option("--png-zmin", r.exports.png_zmin,
                 "Bottom of the height band of --png, metres (default: the walls' band, found in the map)")
      ->needs(png_opt);
  app.add_option("--png-zmax", r.exports.png_zmax,
                 "Top of the height band of --png, metres (default: the walls' band)")
      ->needs(png_opt);
  auto* nav_opt = app.add_option("--export-nav", r.exports.nav_dir,
                                 "Folder for the 2-D navigation grid as map.pgm and map.yaml (ROS/nav2 map_server "
                                 "format) of the band --nav-* (or the --config file's nav.*) sets");
  app.add_option("--nav-floor-z", r.exports.nav_floor_z, "Height of the floor in the map frame, metres (nav.floor_z; 0)")
      ->needs(nav_opt);
  app.add_option("--nav-min-height", r.exports.nav_min_height,
                 "The band starts this far above the floor, metres (nav.min_height; 0.25)")
      ->needs(nav_opt);
  app.add_option("--nav-max-height", r.exports.nav_max_height,
                 "The band ends this far above the floor: the robot's height, metres (nav.max_height; 1.5)")
      ->needs(nav_opt);
  app.add_option("--nav-min-free-fraction", r.exports.nav_min_free_fraction,
                 "A column with nothing occupied in the band is free when this fraction of its layers holds free "
                 "cells (nav.min_free_fraction; 0.5)")
      ->needs(nav_opt);
  app.add_option("--nav-mode", r.exports.nav_mode,
                 "trinary: occupied, free, unknown as map_saver writes them; scale: each column's cost 0..100")
      ->capture_default_str()
      ->check(CLI::IsMember({"trinary", "scale"}))
      ->needs(nav_opt);
}

// The filter's threads, the pose correction, the drive report and paging.
void addRunOptions(CLI::App& app, map_io::MapRequest& r) {
  app.add_option("--threads", r.threads, "Filter threads (the map is the same for any count)")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 256));
  app.add_option(
         "--pose-correction", r.pose_correction,
         "Correct odometry drift before mapping: none, scan-match or rbpf (2-D SLAM on a planar cut of "
         "each scan); default: the config's pose_correction.mode")
      ->capture_default_str();
  app.add_option("--particles", r.particles, "Particles of --pose-correction rbpf")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 1000));
  app.add_option("--corrected-out", r.corrected_out,
                 "CSV of the corrected body pose of every mapped scan (utime,x,y,z,qw,qx,qy,qz)");
  app.add_option(
         "--report-every", r.report_every,
         "Print a row every this many seconds of scan time: scans, mean and largest ms per scan, map MB, "
         "resident MB, cells")
      ->check(CLI::PositiveNumber);
  auto* page_dir_opt =
      app.add_option("--page-dir", r.page_dir,
                     "Keep the map's far regions in page files in this folder while mapping (the "
                     "map is the same; memory holds the regions near the sensor)");
  app.add_option("--page-out-distance", r.page_out_distance,
                 "With --page-dir: regions farther than this from the sensor are paged out, metres")
      ->check(CLI::PositiveNumber)
      ->needs(page_dir_opt)
      ->capture_default_str();
}

// One input at a time; the odometry comes from one place.
void addExclusions(CLI::App& app) {
  auto* pcap_opt = app.get_option("--pcap");
  auto* lcm_opt = app.get_option("--lcm-log");
  auto* pcd_opt = app.get_option("--pcd");
  auto* bag_opt = app.get_option("--rosbag2");
  auto* odo_opt = app.get_option("--odometry");
  auto* static_opt = app.get_option("--static");
  odo_opt->excludes(static_opt);
  pcd_opt->excludes(pcap_opt)->excludes(lcm_opt)->excludes(odo_opt)->excludes(static_opt);
  app.get_option("--from-map")->excludes(pcap_opt)->excludes(lcm_opt)->excludes(pcd_opt)->excludes(bag_opt);
  lcm_opt->excludes(pcap_opt);
  bag_opt->excludes(pcap_opt)->excludes(lcm_opt)->excludes(pcd_opt);
  app.get_option("--pose-topic")->excludes(odo_opt)->excludes(static_opt);
}

}  // namespace

void defineCommandLine(CLI::App& app, MapOptions& o) {
  app.description(kDescription);
  map_io::MapRequest& r = o.request;
  addMapOptions(app, r);
  addInputOptions(app, r);
  addExportOptions(app, r);
  addRunOptions(app, r);
  app.add_option("--log-level", o.log_level, "trace|debug|info|warn|error")->capture_default_str();
  app.add_option("--from-map", r.from_map, "Export this map file or daemon snapshot instead of mapping")
      ->check(CLI::ExistingFile);
  addExclusions(app);
}

void noteGivenFlags(const CLI::App& app, map_io::MapRequest& r) {
  const auto given = [&app](const char* flag) { return app.count(flag) > 0; };
  r.given.calib = given("--calib");
  r.given.out = given("--out");
  r.given.odometry = given("--odometry");
  r.given.pose_topic = given("--pose-topic");
  r.given.resolution = given("--resolution");
  r.given.max_range = given("--max-range");
  r.given.min_range = given("--min-range");
  r.given.threads = given("--threads");
  r.given.time_base = given("--time");
  r.given.pose_correction = given("--pose-correction");
  r.given.particles = given("--particles");
}

}  // namespace ogf::map_program
