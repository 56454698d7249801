// ogf-map: the mapping pipeline offline, as fast as the machine allows. Scans from a PCAP (with odometry
// from a file, or a tripod), an LCM log, a ROS 2 bag (with its own poses) or PCD files go through the same
// ScanMapper the daemon runs; the result is a map file and optional CSV, PLY, OctoMap and PNG exports. This
// file owns the command line, the logs, the progress bar and the exit code; the work is in ogf_map_io.
// --from-map exports a map made before (a map file or a daemon snapshot) without mapping.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>
#include <vector>

#include <ogf/filter/map_file.hpp>
#include <ogf/mapper_daemon/mapper_options.hpp>
#include <ogf/transport/logging.hpp>

#include "ogf/common/command_line.hpp"
#include "ogf/map_formats/cell_csv.hpp"
#include "ogf/map_formats/cell_pcd.hpp"
#include "ogf/map_formats/cell_ply.hpp"
#include "ogf/map_io/drive_report.hpp"
#include "ogf/map_io/lcm_log_scans.hpp"
#include "ogf/map_formats/map_cells.hpp"
#include "ogf/map_io/map_config_file.hpp"
#include "ogf/map_formats/map_loader.hpp"
#include "ogf/map_formats/octomap_export.hpp"
#include "ogf/map_io/odometry_file.hpp"
#include "ogf/map_io/offline_mapping.hpp"
#include "ogf/map_io/pcap_scans.hpp"
#include "ogf/map_io/pcd_file.hpp"
#include "ogf/map_io/topdown_png.hpp"
#include "ogf/rosbag/bag_packets.hpp"
#include "ogf/map_io/bag_poses.hpp"
#include "ogf/rosbag/ros_messages.hpp"

namespace {

namespace mio = ogf::map_io;
using Clock = std::chrono::steady_clock;

using ogf::cli::kExitOk;
constexpr int kExitNothingMapped = 1;  // also: an output could not be written
using ogf::cli::kExitUsage;  // bad flags or configuration
constexpr int kUncoveredWarnings = 5;  // scans described one by one; the rest only counted

// A one-line bar on stderr, redrawn at most 10 times a second, only when stderr is a terminal.
class ProgressBar {
 public:
  ProgressBar() : enabled_(isatty(STDERR_FILENO) == 1) {}
  void update(double fraction, std::int64_t scans) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (drawn_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    drawn_ = true;
    constexpr int kWidth = 40;
    const double f = fraction < 0.0 ? 0.0 : (fraction > 1.0 ? 1.0 : fraction);
    const int filled = static_cast<int>(f * kWidth);
    std::fprintf(stderr, "\r[%s%s] %3d%% scans %lld", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                 std::string(static_cast<std::size_t>(kWidth - filled), ' ').c_str(), static_cast<int>(f * 100.0),
                 static_cast<long long>(scans));
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_ && drawn_) std::fprintf(stderr, "\r%s\r", std::string(70, ' ').c_str());
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point last_;
};

struct Options {
  std::string out, config_path, pcap, calib, odometry, lcm_log, rosbag2, time_base = "auto";
  std::string packets_topic, pose_topic, body_frame = "base_link";
  std::string scan_channel = "VELODYNE_SCAN", pose_channel = "POSE", packets_channel = "VELODYNE_PACKETS";
  std::vector<std::string> pcd;
  bool is_static = false;
  double resolution = 0.2, max_range = 30.0, min_range = 0.4;
  double report_every = 0.0;
  std::string page_dir;
  double page_out_distance = 60.0;
  int threads = 1;
  std::string export_ply, export_csv, export_pcd, export_bt, png_dir, from_map;
  std::optional<double> png_zmin, png_zmax;  // default: the walls' band (map_io::wallBand)
  std::string log_level = "info";
  std::string pose_correction = "none", corrected_out;
  std::size_t particles = 30;
};

void logProblems(const std::vector<std::string>& problems, std::int64_t total) {
  for (const auto& p : problems) spdlog::warn("{}", p);
  if (total > static_cast<std::int64_t>(problems.size()))
    spdlog::warn("{} more problems like these not shown", total - static_cast<std::int64_t>(problems.size()));
}

// Hands the odometry read from `source` to the run and says what it kept.
void useOdometry(const std::string& source, const std::vector<ogf::fusion::Pose>& poses,
                 mio::OfflineMapping& run) {
  run.setOdometry(poses);
  const auto& c = run.counts();
  if (c.poses_rejected > 0)
    spdlog::warn("{}: {} poses rejected (out of order, duplicate time, NaN or not a unit quaternion)", source,
                 c.poses_rejected);
  if (const auto span = run.odometrySpan())
    spdlog::info("{}: {} poses, utime {} .. {} ({:.1f} s)", source, c.poses_accepted, span->first,
                 span->second, static_cast<double>(span->second - span->first) * 1e-6);
  else
    spdlog::warn("{}: no usable pose: every scan will be left out", source);
}

// Reads odometry into the run; false when the file cannot be read at all.
bool loadOdometry(const std::string& path, const std::string& channel, mio::OfflineMapping& run) {
  auto odo = mio::readOdometry(path, channel);
  if (!odo) {
    spdlog::error("{}", odo.error().message);
    return false;
  }
  logProblems(odo->problems, odo->skipped);
  useOdometry(path, odo->poses, run);
  return true;
}

// Logs what went wrong reading raw packets (a damaged tail, skipped messages, gaps); false when they could
// not be read at all.
bool reportPacketProblems(const ogf::Result<mio::PcapScanCounts>& counts) {
  if (!counts) {
    spdlog::error("{}", counts.error().message);
    return false;
  }
  if (!counts->warning.empty()) spdlog::warn("{}", counts->warning);
  if (!counts->gaps.empty()) spdlog::warn("{}", counts->gaps);
  spdlog::info("calibration: {}", counts->calibration);
  return true;
}

// Reads the bag's poses into the run; false when they cannot be read at all.
bool loadBagPoses(const ogf::rosbag::Rosbag2Storage& bag, const ogf::map_io::BagPoseSource& source,
                  const std::string& name, mio::OfflineMapping& run) {
  auto poses = ogf::map_io::readBagPoses(bag, source);
  if (!poses) {
    spdlog::error("{}", poses.error().message);
    return false;
  }
  logProblems(poses->problems, poses->skipped);
  spdlog::info("{}: poses of {} in {} from {} messages ({})", name,
               poses->child_frame.empty() ? "?" : poses->child_frame,
               poses->parent_frame.empty() ? "?" : poses->parent_frame, poses->messages, source.type);
  useOdometry(name, poses->poses, run);
  return true;
}

// The --export-* files and --png of `map`; false when one failed (each failure logged).
bool writeExports(const ogf::filter::BandedOgf& map, const Options& o) {
  bool ok = true;
  if (o.export_csv.empty() && o.export_ply.empty() && o.export_pcd.empty() && o.export_bt.empty() && o.png_dir.empty())
    return ok;
  for (const std::string* path : {&o.export_csv, &o.export_ply, &o.export_pcd, &o.export_bt}) {
    const auto parent = std::filesystem::path(*path).parent_path();
    std::error_code ec;
    if (!path->empty() && !parent.empty()) std::filesystem::create_directories(parent, ec);
  }
  const ogf::map_formats::MapCells cells = ogf::map_formats::collectCells(map);
  const auto report = [&](const char* flag, const ogf::Status& st) {
    if (!st) {
      spdlog::error("{}: {}", flag, st.error().message);
      ok = false;
    }
  };
  if (!o.export_csv.empty()) report("--export-csv", ogf::map_formats::writeCellCsv(cells, o.export_csv));
  if (!o.export_ply.empty()) report("--export-ply", ogf::map_formats::writeOccupiedPly(cells, o.export_ply));
  if (!o.export_pcd.empty()) report("--export-pcd", ogf::map_formats::writeOccupiedPcd(cells, o.export_pcd));
  if (!o.export_bt.empty()) {
    auto bt = ogf::map_formats::writeOctomapBinary(cells, o.export_bt);
    if (!bt) report("--export-bt", bt.error());
    else
      spdlog::info("{}: {} occupied and {} free leaves{}", o.export_bt, bt->occupied, bt->free,
                   bt->out_of_range > 0 ? fmt::format(", {} cells beyond OctoMap's extent left out", bt->out_of_range)
                                        : std::string());
  }
  if (!o.png_dir.empty()) {
    const auto band = ogf::tools::pictureBand(mio::wallBand(cells), o.png_zmin, o.png_zmax, "the map");
    auto png = mio::writeTopDownPngs(cells, {band.z_min, band.z_max}, o.png_dir);
    if (!png) report("--png", png.error());
    else
      spdlog::info("{}: occupancy.png and entropy.png of {} x {} cell columns, z {:.2f} to {:.2f} m ({})", o.png_dir,
                   png->width, png->height, band.z_min, band.z_max, band.why);
  }
  return ok;
}

// --from-map: the exports of a map made before (a map file or a daemon snapshot), no mapping.
int exportMapFile(const Options& o) {
  auto loaded = ogf::map_formats::loadOgfMap(o.from_map);
  if (!loaded) {
    spdlog::error("--from-map: {}", loaded.error().message);
    return kExitNothingMapped;
  }
  int rc = kExitOk;
  if (!o.out.empty()) {
    if (auto st = ogf::filter::saveMapFile(loaded->map, o.out); !st) {
      spdlog::error("--out: {}", st.error().message);
      rc = kExitNothingMapped;
    }
  }
  if (!writeExports(loaded->map, o)) rc = kExitNothingMapped;
  std::printf("map %s cells %zu\n", loaded->kind == "snapshot" ? "snapshot" : "file", loaded->map.allocatedCells());
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{
      "Builds an Occupancy Grid Filter map offline, from one input:\n"
      "  --pcap FILE [--calib FILE] (--odometry FILE | --static)   a Velodyne capture\n"
      "  --lcm-log FILE                                             lidar_scan_t and poses as lcm-logger records them\n"
      "  --rosbag2 DIR                                              a ROS 2 bag (sqlite3): VelodyneScan packets,\n"
      "                                                             poses from its Odometry or /tf\n"
      "  --pcd FILE...                                              PCL point clouds (rays from each VIEWPOINT)\n"
      "or exports a map already made: --from-map FILE (a map file or a daemon snapshot) with any --export-*\n"
      "and --png; then --out is optional and the last line is  map <kind> cells <allocated cells>.\n"
      "With --pose-correction scan-match|rbpf the odometry's drift is corrected scan by scan before mapping.\n"
      "Odometry: CSV `utime,x,y,z,qw,qx,qy,qz` (utime in us on the clock --time names) or an LCM log with\n"
      "ogf.odometry_t or bot_core.pose_t on POSE. Scans the odometry does not cover are counted and left out,\n"
      "never extrapolated; when none is covered because the two are on different clocks, the log says which\n"
      "--time fixes it. --static (pose_source: static) holds the body at static_pose, the origin by default.\n"
      "--config reads ogf-mapper's configuration file (ogf-mapper --print-config lists its keys); flags override it.\n"
      "At the end one line on stdout:\n"
      "  scans <mapped> measurements <cell measurements> cells <allocated cells> seconds <wall time>\n"
      "Exit 0 when at least one scan was mapped and every output written, 1 when nothing could be mapped or\n"
      "an output failed, 2 on bad flags or configuration."};
  auto* out_opt = app.add_option("--out", o.out, "Map file to write (ogf map format, see ogf/filter/map_file.hpp)");
  app.add_option("--config", o.config_path,
                 "ogf-mapper's YAML configuration (map, filter, fusion, time_base, pose_source, static_pose, "
                 "pose_correction; its other keys are ignored here); flags override it")
      ->check(CLI::ExistingFile);
  auto* res_opt = app.add_option("--resolution", o.resolution, "Cell size, metres")
                      ->capture_default_str()->check(ogf::cli::positive());
  auto* max_opt = app.add_option("--max-range", o.max_range, "Rays are cut here (free cells only beyond), metres")
                      ->capture_default_str()->check(ogf::cli::positive());
  auto* min_opt = app.add_option("--min-range", o.min_range, "Returns closer than this are ignored, metres")
                      ->capture_default_str()->check(ogf::cli::nonNegative());
  auto* pcap_opt = app.add_option("--pcap", o.pcap, "Velodyne capture (pcap or pcapng)");
  auto* calib_opt =
      app.add_option("--calib", o.calib, "Calibration for --pcap or --rosbag2: VeloView XML or ROS YAML");
  auto* odo_opt = app.add_option("--odometry", o.odometry, "Odometry: CSV or LCM log (POSE)");
  auto* static_opt = app.add_flag("--static", o.is_static,
                                  "The sensor does not move (a tripod): the body at the config's static_pose, by "
                                  "default the origin");
  auto* lcm_opt = app.add_option("--lcm-log", o.lcm_log, "LCM log with scans (VELODYNE_SCAN, else the raw packets on VELODYNE_PACKETS) and poses (POSE)");
  auto* pcd_opt = app.add_option("--pcd", o.pcd, "PCD files, one scan each");
  auto* bag_opt =
      app.add_option("--rosbag2", o.rosbag2,
                     "ROS 2 bag folder (or one .db3): velodyne_msgs/msg/VelodyneScan packets, poses from "
                     "nav_msgs/msg/Odometry or tf2_msgs/msg/TFMessage; --time defaults to host (ROS stamps)");
  app.add_option("--packets-topic", o.packets_topic,
                 "VelodyneScan topic of --rosbag2 (default: the only one)")
      ->needs(bag_opt);
  auto* pose_topic_opt =
      app.add_option("--pose-topic", o.pose_topic,
                     "Odometry or TFMessage topic of --rosbag2 (default: the only Odometry topic, else /tf)")
          ->needs(bag_opt);
  app.add_option("--body-frame", o.body_frame, "The body's TF child frame when the poses come from /tf")
      ->capture_default_str()
      ->needs(bag_opt);
  auto* time_opt =
      app.add_option("--time", o.time_base,
                     "Clock the odometry is on: device (scan device time), host (receive time) or auto (device for "
                     "scans whose device time is GPS/PPS-locked UTC, host otherwise; ogf-mapper's rule). Default: "
                     "the config's time_base, else auto (host for --rosbag2)")
          ->check(CLI::IsMember({"auto", "device", "host"}))
          ->capture_default_str();
  app.add_option("--scan-channel", o.scan_channel, "Scan channel in --lcm-log")->capture_default_str();
  app.add_option("--packets-channel", o.packets_channel,
                 "Raw packet channel in --lcm-log, decoded when the log has no scans")
      ->capture_default_str();
  app.add_option("--pose-channel", o.pose_channel, "Pose channel in LCM logs")->capture_default_str();
  app.add_option("--export-csv", o.export_csv, "Every allocated cell: x,y,z,p,class,variance (cell centres, metres)");
  app.add_option("--export-ply", o.export_ply, "Occupied cells as binary PLY (x, y, z, p, variance)");
  app.add_option("--export-pcd", o.export_pcd, "Occupied cells as binary PCD v0.7 (x, y, z, p, variance)");
  app.add_option("--export-bt", o.export_bt, "OctoMap binary tree (.bt) for octovis");
  auto* png_opt = app.add_option("--png", o.png_dir, "Folder for top-down occupancy.png and entropy.png");
  app.add_option("--png-zmin", o.png_zmin,
                 "Bottom of the height band of --png, metres (default: the walls' band, found in the map)")
      ->needs(png_opt);
  app.add_option("--png-zmax", o.png_zmax, "Top of the height band of --png, metres (default: the walls' band)")
      ->needs(png_opt);
  auto* threads_opt = app.add_option("--threads", o.threads, "Filter threads (the map is the same for any count)")
                          ->capture_default_str()
                          ->check(ogf::cli::between(1, 256));
  auto* correction_opt =
      app.add_option("--pose-correction", o.pose_correction,
                     "Correct odometry drift before mapping: none, scan-match or rbpf (2-D SLAM on a planar cut of "
                     "each scan); default: the config's pose_correction.mode")
          ->capture_default_str();
  auto* particles_opt = app.add_option("--particles", o.particles, "Particles of --pose-correction rbpf")
      ->capture_default_str()
      ->check(ogf::cli::between(1, 1000));
  app.add_option("--corrected-out", o.corrected_out,
                 "CSV of the corrected body pose of every mapped scan (utime,x,y,z,qw,qx,qy,qz)");
  app.add_option("--report-every", o.report_every,
                 "Print a row every this many seconds of scan time: scans, mean and largest ms per scan, map MB, "
                 "resident MB, cells")
      ->check(CLI::PositiveNumber);
  auto* page_dir_opt = app.add_option("--page-dir", o.page_dir,
                                      "Keep the map's far regions in page files in this folder while mapping (the "
                                      "map is the same; memory holds the regions near the sensor)");
  app.add_option("--page-out-distance", o.page_out_distance,
                 "With --page-dir: regions farther than this from the sensor are paged out, metres")
      ->check(CLI::PositiveNumber)
      ->needs(page_dir_opt)
      ->capture_default_str();
  app.add_option("--log-level", o.log_level, "trace|debug|info|warn|error")->capture_default_str();
  odo_opt->excludes(static_opt);
  pcd_opt->excludes(pcap_opt)->excludes(lcm_opt)->excludes(odo_opt)->excludes(static_opt);
  auto* from_opt = app.add_option("--from-map", o.from_map, "Export this map file or daemon snapshot instead of mapping")
                       ->check(CLI::ExistingFile);
  from_opt->excludes(pcap_opt)->excludes(lcm_opt)->excludes(pcd_opt)->excludes(bag_opt);
  lcm_opt->excludes(pcap_opt);
  bag_opt->excludes(pcap_opt)->excludes(lcm_opt)->excludes(pcd_opt);
  pose_topic_opt->excludes(odo_opt)->excludes(static_opt);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);

  if (!ogf::transport::setupLoggingAt("ogf-map", "--log-level", o.log_level)) return kExitUsage;
  if (!o.from_map.empty()) return exportMapFile(o);
  if (o.pcap.empty() && o.lcm_log.empty() && o.pcd.empty() && o.rosbag2.empty()) {
    spdlog::error("no input: give --pcap, --lcm-log, --rosbag2, --pcd or --from-map");
    return kExitUsage;
  }
  if (calib_opt->count() > 0 && o.pcap.empty() && o.lcm_log.empty() && o.rosbag2.empty()) {
    spdlog::error("--calib applies to raw packets: --pcap, --rosbag2 or an --lcm-log of packets");
    return kExitUsage;
  }
  if (out_opt->count() == 0) {
    spdlog::error("--out is required when mapping");
    return kExitUsage;
  }
  ogf::mapper_daemon::MapperOptions file;  // the defaults when there is no --config
  std::optional<mio::OfflineConfig> read_config;
  if (!o.config_path.empty()) {
    auto read = mio::readOfflineConfig(o.config_path, ogf::mapper_daemon::kUsedByMap);
    if (!read) {
      spdlog::error("--config: {}", read.error().message);
      return ogf::cli::exitCodeFor(read.error());
    }
    if (const auto note = read->unusedNote("ogf-map"); !note.empty()) spdlog::info("--config: {}", note);
    file = read->options;
    read_config = std::move(*read);
  }
  // The clock: --time, else the file's time_base, else auto; a bag's packet stamps and its poses' header
  // stamps are both on the ROS (host) clock.
  if (time_opt->count() == 0) {
    const bool file_sets_clock = read_config && read_config->sets("time_base");
    if (file_sets_clock) o.time_base = file.time_base == mio::TimeBase::kHost     ? "host"
                                       : file.time_base == mio::TimeBase::kDevice ? "device"
                                                                                   : "auto";
    else if (!o.rosbag2.empty()) o.time_base = "host";
  }
  // pose_source: static in the file is --static, unless the command line names the odometry.
  if (file.pose_source == ogf::mapper_daemon::PoseSource::kStatic && odo_opt->count() == 0 &&
      pose_topic_opt->count() == 0 && o.pcd.empty())
    o.is_static = true;
  if (!o.pcap.empty() && o.odometry.empty() && !o.is_static) {
    spdlog::error("--pcap needs --odometry FILE or --static");
    return kExitUsage;
  }

  ogf::pipeline::MapperConfig config = file.map;
  if (o.config_path.empty() || res_opt->count() > 0) config.setResolution(o.resolution);
  if (o.config_path.empty() || max_opt->count() > 0) config.fusion.measurement.max_range_m = o.max_range;
  if (o.config_path.empty() || min_opt->count() > 0) config.fusion.measurement.min_range_m = o.min_range;
  if (threads_opt->count() > 0) config.filter.threads = o.threads;
  auto created = mio::OfflineMapping::create(config);
  if (!created) {
    spdlog::error("configuration: {}", created.error().message);
    return ogf::cli::exitCodeFor(created.error());
  }
  mio::OfflineMapping& run = *created;
  ogf::correction::ScanPoseCorrectionConfig cc = file.pose_correction;
  if (correction_opt->count() > 0) {
    const auto mode = ogf::slam::parseCorrectionMode(o.pose_correction);
    if (!mode) {
      spdlog::error("--pose-correction: {}", mode.error().message);
      return kExitUsage;
    }
    cc.corrector.mode = *mode;
  }
  if (particles_opt->count() > 0) cc.corrector.slam.particles = o.particles;
  o.pose_correction = std::string(ogf::slam::toString(cc.corrector.mode));
  if (cc.corrector.mode != ogf::slam::CorrectionMode::kNone) {
    if (o.is_static || !o.pcd.empty()) {
      spdlog::error(
          "--pose-correction needs a moving sensor with odometry (--pcap with --odometry, --lcm-log or "
          "--rosbag2)");
      return kExitUsage;
    }
    auto correction = ogf::correction::ScanPoseCorrection::create(cc);
    if (!correction) {
      spdlog::error("--pose-correction: {}", correction.error().message);
      return kExitUsage;
    }
    run.setPoseCorrection(std::move(*correction));
  } else if (!o.corrected_out.empty()) {
    spdlog::error("--corrected-out needs --pose-correction scan-match or rbpf");
    return kExitUsage;
  }
  // Inputs that are not there are said so by the flag that named them, before anything is read.
  for (const auto& [flag, path] : {std::pair<const char*, const std::string&>{"--pcap", o.pcap},
                                   {"--lcm-log", o.lcm_log}, {"--odometry", o.odometry}}) {
    if (!path.empty() && !std::filesystem::is_regular_file(path)) {
      spdlog::error("{}: {}: no such file", flag, path);
      return kExitNothingMapped;
    }
  }
  // A bag: what it holds and which topics are read, before anything is mapped.
  std::optional<ogf::rosbag::Rosbag2Storage> bag;
  std::string packets_topic;
  std::optional<ogf::map_io::BagPoseSource> bag_poses;
  if (!o.rosbag2.empty()) {
    auto opened = ogf::rosbag::Rosbag2Storage::open(o.rosbag2);
    if (!opened) {
      spdlog::error("--rosbag2: {}", opened.error().message);
      return kExitNothingMapped;
    }
    bag = std::move(*opened);
    if (const auto found = bag->whereFound(); !found.empty()) spdlog::info("{}", found);
    if (const auto others = ogf::rosbag::undecodedTopicsSummary(bag->topics()); !others.empty())
      spdlog::info("{}: not read (types ogf does not decode): {}", o.rosbag2, others);
    auto topic = ogf::rosbag::choosePacketTopic(*bag, o.packets_topic);
    if (!topic) {
      spdlog::error("--packets-topic: {}", topic.error().message);
      return kExitUsage;
    }
    if (!*topic) {
      spdlog::error("{}: no {} topic: nothing to map", o.rosbag2, ogf::rosbag::kVelodyneScanType);
      return kExitNothingMapped;
    }
    packets_topic = **topic;
    if (!o.is_static && o.odometry.empty()) {
      auto source = ogf::map_io::choosePoseSource(*bag, o.pose_topic, o.body_frame);
      if (!source) {
        spdlog::error("--pose-topic: {}", source.error().message);
        return kExitUsage;
      }
      if (!*source) {
        spdlog::error("{}: no {} topic and no /tf: give --pose-topic, --odometry FILE or --static", o.rosbag2,
                      ogf::rosbag::kOdometryType);
        return kExitUsage;
      }
      bag_poses = **source;
    }
  }

  const auto& m = config.fusion.measurement;
  if (!o.page_dir.empty()) {
    if (auto st = run.setPaging(o.page_dir, o.page_out_distance); !st) {
      spdlog::error("--page-dir: {}", st.error().message);
      return kExitUsage;
    }
    const double reach = ogf::persistence::MapPager::churnDistance(m.max_range_m, m.resolution_m);
    if (o.page_out_distance < reach)
      spdlog::warn("--page-out-distance {} m is within the scans' reach (max range plus two regions, {:.1f} m): "
                   "regions will go out and come back scan after scan (the same map, more disk traffic)",
                   o.page_out_distance, reach);
  }
  spdlog::info("resolution {} m, range {} .. {} m, filter threads {}", m.resolution_m, m.min_range_m, m.max_range_m,
               run.mapper().filter().config().threads);

  const auto start = Clock::now();
  ProgressBar bar;
  const mio::TimeBase base = o.time_base == "host"     ? mio::TimeBase::kHost
                            : o.time_base == "device" ? mio::TimeBase::kDevice
                                                      : mio::TimeBase::kAuto;
  const Eigen::Isometry3d static_pose = file.static_pose.bodyFromSensor();
  int uncovered_told = 0;
  std::string odometry_source;
  std::optional<mio::DriveReport> report;
  if (o.report_every > 0.0) report.emplace(o.report_every, stdout);
  const auto addScan = [&](const mio::ScanRecord& scan) {
    const auto began = Clock::now();
    const mio::ScanOutcome outcome =
        o.is_static ? run.addStaticScan(scan, static_pose) : run.addScan(scan, base);
    if (report && outcome == mio::ScanOutcome::kMapped) {
      const auto& f = run.mapper().filter();
      report->add({scan.points(base).start_utime,
                   std::chrono::duration<double, std::milli>(Clock::now() - began).count(), f.memoryBytes(),
                   f.allocatedCells() + run.pagedBlocks().blocks * f.cellsPerBlock()});
    }
    if (o.is_static) return;
    if (outcome == mio::ScanOutcome::kUncovered && uncovered_told++ < kUncoveredWarnings) {
      const auto span = run.odometrySpan();
      const std::int64_t t = scan.points(base).start_utime;
      spdlog::warn("scan {} at utime {} ({} time) is not covered by the odometry of {} ({}); left out", scan.seq, t,
                   ogf::fusion::clockName(scan.clock(base)), odometry_source,
                   span ? fmt::format("utime {} .. {}", span->first, span->second) : std::string("no poses"));
    }
  };
  const auto progress = [&](double f) { bar.update(f, run.counts().scans_in); };
  const auto decoderConfig = [&] {
    mio::PcapScanConfig pc;
    if (!o.calib.empty()) pc.calibration = o.calib;
    pc.min_range_m = m.min_range_m;
    return pc;
  };

  bool input_failed = false;
  if (!o.pcap.empty() || !o.lcm_log.empty()) {
    if (!o.is_static) {
      odometry_source = o.odometry.empty() ? o.lcm_log : o.odometry;
      if (!loadOdometry(odometry_source, o.pose_channel, run)) return kExitNothingMapped;
    }
    if (!o.pcap.empty()) {
      auto counts = mio::readPcapScans(o.pcap, decoderConfig(), addScan, progress);
      if (!reportPacketProblems(counts)) {
        input_failed = true;
      } else {
        spdlog::info("{}: {} scans, {} points, {} data packets, {} lost, {} bad", o.pcap, counts->scans,
                     counts->points, counts->data_packets, counts->packets_lost, counts->bad_packets);
      }
    } else {
      auto counts = mio::readLcmLogScans(o.lcm_log, o.scan_channel, addScan, progress);
      if (!counts) {
        spdlog::error("{}", counts.error().message);
        input_failed = true;
      } else {
        logProblems(counts->problems, counts->skipped);
        if (!counts->gaps.empty()) spdlog::warn("{}", counts->gaps);
        spdlog::info("{}: {} events, {} scans on {}", o.lcm_log, counts->events, counts->scans, o.scan_channel);
      }
      if (counts && counts->scans == 0) {
        // A log of the raw packets only: decode them as the driver did live.
        auto decoded =
            mio::readLcmLogPacketScans(o.lcm_log, o.packets_channel, decoderConfig(), addScan, progress);
        if (!reportPacketProblems(decoded)) {
          input_failed = true;
        } else {
          spdlog::info("{}: no scans on {}; {} scans decoded from the packets on {} ({} data packets, {} lost, {} bad)",
                       o.lcm_log, o.scan_channel, decoded->scans, o.packets_channel, decoded->data_packets,
                       decoded->packets_lost, decoded->bad_packets);
        }
      }
    }
  } else if (bag) {
    if (!o.is_static) {
      odometry_source = bag_poses ? o.rosbag2 + " " + bag_poses->topic : o.odometry;
      const bool loaded = bag_poses ? loadBagPoses(*bag, *bag_poses, odometry_source, run)
                                    : loadOdometry(o.odometry, o.pose_channel, run);
      if (!loaded) return kExitNothingMapped;
    }
    auto counts = mio::readRosbagPacketScans(*bag, packets_topic, decoderConfig(), addScan, progress);
    if (!reportPacketProblems(counts)) {
      input_failed = true;
    } else {
      spdlog::info("{}: {} scans decoded from {} ({} data packets, {} lost, {} bad)", o.rosbag2,
                   counts->scans, packets_topic, counts->data_packets, counts->packets_lost,
                   counts->bad_packets);
    }
  } else {
    for (std::size_t i = 0; i < o.pcd.size(); ++i) {
      auto cloud = mio::readPcdFile(o.pcd[i]);
      if (!cloud) {
        spdlog::error("{}; file skipped", cloud.error().message);
        continue;
      }
      if (cloud->non_finite > 0) spdlog::info("{}: {} non-finite points dropped", o.pcd[i], cloud->non_finite);
      run.addCloud(cloud->viewpoint_translation, cloud->points);
      progress(static_cast<double>(i + 1) / static_cast<double>(o.pcd.size()));
    }
  }
  bar.finish();

  const mio::OfflineCounts& c = run.counts();
  if (c.scans_uncovered > 0)
    spdlog::warn("{} of {} scans not covered by the odometry of {}: left out (never extrapolated)",
                 c.scans_uncovered, c.scans_in, odometry_source);
  if (c.scans_empty > 0) spdlog::info("{} scans gave no measurement (no return within range)", c.scans_empty);
  // No scan covered and the scans far from the odometry: the two are on different clocks; say which
  // --time or time_base fixes it.
  const bool other_clocks = c.scans_mapped + c.scans_empty == 0 && run.clockMismatch().has_value();
  if (other_clocks) spdlog::warn("clocks: {}", run.clockMismatch()->describe("--time"));
  if (c.scans_mapped == 0) {
    spdlog::error("nothing could be mapped ({} scans read{}{})", c.scans_in, input_failed ? ", input unreadable" : "",
                  other_clocks ? "; scans and odometry are on different clocks: see the clocks line above" : "");
    return kExitNothingMapped;
  }

  // Output folders are created as needed, as --png's is.
  for (const std::string* path : {&o.out}) {
    const auto parent = std::filesystem::path(*path).parent_path();
    std::error_code ec;
    if (!path->empty() && !parent.empty()) std::filesystem::create_directories(parent, ec);
  }
  int rc = kExitOk;
  if (const auto* pager = run.pager()) {
    const auto pc = pager->counts();
    spdlog::info("paging: {} regions written, {} read back; {} regions ({} blocks, {:.1f} MB) on disk at the end",
                 pc.pages_written, pc.pages_read, pc.regions_out, pc.blocks_out, static_cast<double>(pc.bytes_out) / 1e6);
    // The map file and the exports hold the whole map.
    if (auto st = run.bringInAll(); !st) {
      spdlog::error("--page-dir: {}", st.error().message);
      return kExitNothingMapped;
    }
  }
  const auto& filter = run.mapper().filter();
  if (auto st = ogf::filter::saveMapFile(filter, o.out); !st) {
    spdlog::error("--out: {}", st.error().message);
    rc = kExitNothingMapped;
  }
  if (!writeExports(filter, o)) rc = kExitNothingMapped;
  if (!o.corrected_out.empty()) {
    if (auto st = mio::writeOdometryCsv(o.corrected_out, run.correctedPoses()); !st) {
      spdlog::error("--corrected-out: {}", st.error().message);
      rc = kExitNothingMapped;
    } else {
      spdlog::info("{}: {} corrected poses ({})", o.corrected_out, run.correctedPoses().size(), o.pose_correction);
    }
  }
  if (report) report->finish();
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("scans %lld measurements %lld cells %zu seconds %.2f checksum %016llx\n",
              static_cast<long long>(c.scans_mapped), static_cast<long long>(c.measurements), filter.allocatedCells(),
              seconds, static_cast<unsigned long long>(filter.checksum()));
  return rc;
}
